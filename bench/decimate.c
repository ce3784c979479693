// decimate.c — the benchmark's mesh simplifier: vertex clustering on a uniform grid (Rossignac and Borrel,
// 1993), to about TRIANGLES triangles, written as an OBJ of `v` and `f` lines.
//
// usage: decimate IN.obj OUT.obj TRIANGLES
//
// The vertices of each cubic grid cell merge into one, at their mean; a triangle whose three corners fall in
// three different cells survives (with its winding) and the others vanish, as do repeats of a surviving
// triangle. The cell size is the one (n cells along the bounding box's longest side, n searched by bisection)
// whose result is nearest TRIANGLES. The surface keeps its place and extent, so a scene framed for the
// original frames the result too; bench/run.sh uses it for the small end of its scaling table, below the
// Stanford bunny's 69,451 triangles. Deterministic: the same input gives the same bytes.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_io.h"

// A cluster numbering of the vertices for one grid: cluster[v] in 0..count-1, in order of first vertex.
typedef struct clustering {
    uint32_t *cluster;
    size_t count;
} clustering;

// Open-addressing set of keys (0 = empty) with a value each; size a power of two, kept under half full.
typedef struct table {
    uint64_t *keys;
    uint32_t *vals;
    size_t mask;
} table;

static table table_new(size_t entries) {
    size_t size = 16;
    while (size < 2 * entries) size *= 2;
    table t = {calloc(size, sizeof(uint64_t)), malloc(size * sizeof(uint32_t)), size - 1};
    if (!t.keys || !t.vals) mesh_die("out of memory");
    return t;
}

static void table_free(table *t) {
    free(t->keys);
    free(t->vals);
}

// The slot of KEY: holding KEY, or empty (keys[slot] == 0) where it belongs.
static size_t table_slot(const table *t, uint64_t key) {
    size_t i = mesh_hash64(key) & t->mask;
    while (t->keys[i] != 0 && t->keys[i] != key) i = (i + 1) & t->mask;
    return i;
}

// Numbers the grid cells of M's vertices for a grid of N cells along the box's longest side.
static clustering cluster(const meshbuf *m, const double lo[3], double side, uint32_t n) {
    clustering c = {malloc(m->nv * sizeof(uint32_t)), 0};
    if (!c.cluster) mesh_die("out of memory");
    table t = table_new(m->nv);
    double scale = n / side;
    for (size_t v = 0; v < m->nv; v++) {
        uint64_t key = 0;
        for (int a = 0; a < 3; a++) {
            double x = floor((m->verts[v].p[a] - lo[a]) * scale);
            uint64_t cell = x < 0 ? 0 : x >= n ? n - 1 : (uint64_t)x; // the far faces of the box: the last cell
            key |= cell << (21 * a);
        }
        key += 1; // 0 marks an empty slot
        size_t s = table_slot(&t, key);
        if (t.keys[s] == 0) {
            t.keys[s] = key;
            t.vals[s] = (uint32_t)c.count++;
        }
        c.cluster[v] = t.vals[s];
    }
    table_free(&t);
    return c;
}

// The key of a triangle of clusters, its corners sorted (so that repeats in any order or winding match).
static uint64_t tri_key(uint32_t a, uint32_t b, uint32_t c, size_t clusters) {
    uint32_t t;
    if (a > b) t = a, a = b, b = t;
    if (b > c) t = b, b = c, c = t;
    if (a > b) t = a, a = b, b = t;
    return ((uint64_t)a * clusters + b) * clusters + c + 1;
}

// Simplifies M on the grid of N cells along SIDE into OUT (NULL: only counts); returns the triangles kept.
static size_t simplify(const meshbuf *m, const double lo[3], double side, uint32_t n, meshbuf *out) {
    clustering c = cluster(m, lo, side, n);
    table seen = table_new(m->nt);
    uint32_t *renumber = NULL; // a cluster's vertex in OUT, UINT32_MAX until first used
    double *sum = NULL;        // per cluster: x, y, z sums and the count
    if (out) {
        renumber = malloc(c.count * sizeof *renumber);
        sum = calloc(c.count * 4, sizeof *sum);
        if (!renumber || !sum) mesh_die("out of memory");
        memset(renumber, 0xff, c.count * sizeof *renumber);
        for (size_t v = 0; v < m->nv; v++) {
            double *s = sum + 4 * (size_t)c.cluster[v];
            for (int a = 0; a < 3; a++) s[a] += m->verts[v].p[a];
            s[3] += 1;
        }
    }
    size_t kept = 0;
    for (size_t i = 0; i < m->nt; i++) {
        uint32_t k[3];
        for (int j = 0; j < 3; j++) k[j] = c.cluster[m->tris[i].v[j]];
        if (k[0] == k[1] || k[1] == k[2] || k[2] == k[0]) continue; // collapsed to an edge or a point
        // (the key fits in 64 bits: main refuses inputs of 2^21 vertices or more, so clusters < 2^21)
        uint64_t key = tri_key(k[0], k[1], k[2], c.count);
        size_t s = table_slot(&seen, key);
        if (seen.keys[s] != 0) continue; // a repeat: two sheets merged into one
        seen.keys[s] = key;
        kept++;
        if (!out) continue;
        for (int j = 0; j < 3; j++) {
            if (renumber[k[j]] == UINT32_MAX) {
                const double *s4 = sum + 4 * (size_t)k[j];
                double p[3] = {s4[0] / s4[3], s4[1] / s4[3], s4[2] / s4[3]};
                renumber[k[j]] = mesh_add_vertex(out, p);
            }
            k[j] = renumber[k[j]];
        }
        mesh_add_tri(out, k[0], k[1], k[2]);
    }
    free(renumber);
    free(sum);
    table_free(&seen);
    free(c.cluster);
    return kept;
}

int main(int argc, char **argv) {
    mesh_tool_name("decimate");
    if (argc != 4) {
        fprintf(stderr, "usage: decimate IN.obj OUT.obj TRIANGLES\n");
        return 2;
    }
    char *end;
    long target = strtol(argv[3], &end, 10);
    if (end == argv[3] || *end || target < 1) {
        fprintf(stderr, "decimate: TRIANGLES must be a positive integer\n");
        return 2;
    }
    meshbuf m = {0};
    mesh_read_obj(argv[1], &m);
    if (m.nt == 0) mesh_die("no faces in the input");
    if (m.nv >= (size_t)1 << 21) mesh_die("more than 2^21 vertices: too many for the grid's keys");
    if ((size_t)target >= m.nt) {
        fprintf(stderr, "decimate: TRIANGLES (%ld) must be fewer than the input's %zu\n", target, m.nt);
        mesh_free(&m);
        return 2;
    }
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) lo[a] = hi[a] = m.verts[0].p[a];
    for (size_t v = 1; v < m.nv; v++)
        for (int a = 0; a < 3; a++) {
            if (m.verts[v].p[a] < lo[a]) lo[a] = m.verts[v].p[a];
            if (m.verts[v].p[a] > hi[a]) hi[a] = m.verts[v].p[a];
        }
    double side = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    if (!(side > 0)) mesh_die("the vertices span no volume");
    // Finer grids keep more triangles (not strictly, but nearly): bisect for the first n reaching the
    // target, then take it or the one before, whichever is nearer.
    uint32_t a = 1, b = (uint32_t)1 << 20;
    while (a < b) {
        uint32_t mid = a + (b - a) / 2;
        if (simplify(&m, lo, side, mid, NULL) >= (size_t)target) b = mid;
        else a = mid + 1;
    }
    uint32_t n = a;
    if (n > 1) {
        size_t over = simplify(&m, lo, side, n, NULL) - (size_t)target;
        size_t under = (size_t)target - simplify(&m, lo, side, n - 1, NULL);
        if (under < over) n--;
    }
    meshbuf out = {0};
    simplify(&m, lo, side, n, &out);
    char header[4200];
    snprintf(header, sizeof header, "%s simplified by vertex clustering (%u cells along the longest side) by "
             "bench/decimate.c", argv[1], n);
    mesh_write_obj(argv[2], &out, header);
    fprintf(stderr, "decimate: %zu -> %zu triangles, %zu vertices (%u cells along the longest side)\n", m.nt,
            out.nt, out.nv, n);
    mesh_free(&out);
    mesh_free(&m);
    return 0;
}
