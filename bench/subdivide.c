// subdivide.c — the benchmark's mesh generator: 4:1 midpoint subdivision of a triangle mesh read from an OBJ
// file, LEVELS times (each level quadruples the triangles), written as an OBJ of `v` and `f` lines.
//
// usage: subdivide IN.obj OUT.obj LEVELS
//
// Reads `v` and `f` lines (every index form, negative indices, polygons fanned from their first corner) and
// ignores everything else. Each triangle (a, b, c) becomes (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)
// with the edge midpoints shared by the two triangles of an edge, so a closed mesh stays closed and the
// winding is kept. The surface does not change shape (the points are midpoints): what grows is the number of
// triangles, which is what the benchmark measures. bench/run.sh builds this file with the system compiler.
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct vertex {
    double p[3];
} vertex;

typedef struct tri {
    uint32_t v[3];
} tri;

typedef struct meshbuf {
    vertex *verts;
    size_t nv, capv;
    tri *tris;
    size_t nt, capt;
} meshbuf;

static void die(const char *what) {
    fprintf(stderr, "subdivide: %s\n", what);
    exit(1);
}

static void *grow(void *p, size_t *cap, size_t need, size_t size) {
    if (need <= *cap) return p;
    size_t c = *cap ? *cap : 1024;
    while (c < need) c *= 2;
    void *q = realloc(p, c * size);
    if (!q) die("out of memory");
    *cap = c;
    return q;
}

static uint32_t add_vertex(meshbuf *m, const double p[3]) {
    if (m->nv >= UINT32_MAX) die("too many vertices");
    m->verts = grow(m->verts, &m->capv, m->nv + 1, sizeof *m->verts);
    memcpy(m->verts[m->nv].p, p, sizeof m->verts[0].p);
    return (uint32_t)m->nv++;
}

static void add_tri(meshbuf *m, uint32_t a, uint32_t b, uint32_t c) {
    m->tris = grow(m->tris, &m->capt, m->nt + 1, sizeof *m->tris);
    m->tris[m->nt++] = (tri){{a, b, c}};
}

// The vertex index of an OBJ face corner ("7", "7/2", "7//3", "-1/2/3"): 1-based, or negative from the end.
static uint32_t corner_index(const char *tok, size_t nv, long line) {
    char *end;
    errno = 0;
    long i = strtol(tok, &end, 10);
    if (end == tok || errno || (*end && *end != '/')) {
        fprintf(stderr, "subdivide: line %ld: bad face corner '%s'\n", line, tok);
        exit(1);
    }
    long k = i > 0 ? i - 1 : (long)nv + i;
    if (i == 0 || k < 0 || (size_t)k >= nv) {
        fprintf(stderr, "subdivide: line %ld: vertex index %ld out of range\n", line, i);
        exit(1);
    }
    return (uint32_t)k;
}

static void read_obj(const char *path, meshbuf *m) {
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "subdivide: %s: %s\n", path, strerror(errno));
        exit(1);
    }
    char line[4096];
    long n = 0;
    while (fgets(line, sizeof line, f)) {
        n++;
        if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
            double p[3];
            if (sscanf(line + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) != 3) {
                fprintf(stderr, "subdivide: %s:%ld: expected three coordinates\n", path, n);
                exit(1);
            }
            add_vertex(m, p);
        } else if (line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
            uint32_t first = 0, prev = 0;
            int k = 0;
            char *save = NULL;
            for (char *tok = strtok_r(line + 2, " \t\r\n", &save); tok; tok = strtok_r(NULL, " \t\r\n", &save)) {
                if (tok[0] == '#') break;
                uint32_t v = corner_index(tok, m->nv, n);
                if (k == 0) first = v;
                else if (k >= 2) add_tri(m, first, prev, v);
                prev = v;
                k++;
            }
        }
    }
    if (ferror(f)) die("read error");
    fclose(f);
}

// Open-addressing table from an edge (its two vertex indices, smaller first) to its midpoint's index.
typedef struct edge_table {
    uint64_t *keys; // (lo << 32 | hi) + 1; 0 = empty
    uint32_t *mid;
    size_t mask;
} edge_table;

static uint64_t hash64(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    return x ^ (x >> 33);
}

static uint32_t midpoint(edge_table *t, meshbuf *m, uint32_t a, uint32_t b) {
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint64_t key = ((uint64_t)lo << 32 | hi) + 1;
    for (size_t i = hash64(key) & t->mask;; i = (i + 1) & t->mask) {
        if (t->keys[i] == key) return t->mid[i];
        if (t->keys[i] == 0) {
            double p[3];
            for (int c = 0; c < 3; c++) p[c] = 0.5 * (m->verts[lo].p[c] + m->verts[hi].p[c]);
            t->keys[i] = key;
            return t->mid[i] = add_vertex(m, p);
        }
    }
}

static void subdivide(meshbuf *m) {
    size_t nt = m->nt, size = 1;
    while (size < 4 * nt) size *= 2; // at most 3 nt edges: the table stays under 3/4 full
    edge_table t = {calloc(size, sizeof *t.keys), malloc(size * sizeof *t.mid), size - 1};
    tri *old = m->tris;
    if (!t.keys || !t.mid) die("out of memory");
    m->tris = NULL;
    m->nt = m->capt = 0;
    for (size_t i = 0; i < nt; i++) {
        uint32_t a = old[i].v[0], b = old[i].v[1], c = old[i].v[2];
        uint32_t ab = midpoint(&t, m, a, b), bc = midpoint(&t, m, b, c), ca = midpoint(&t, m, c, a);
        add_tri(m, a, ab, ca);
        add_tri(m, ab, b, bc);
        add_tri(m, ca, bc, c);
        add_tri(m, ab, bc, ca);
    }
    free(old);
    free(t.keys);
    free(t.mid);
}

static void write_obj(const char *path, const meshbuf *m, const char *source, long levels) {
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "subdivide: %s: %s\n", path, strerror(errno));
        exit(1);
    }
    fprintf(f, "# %s subdivided 4:1 %ld times by bench/subdivide.c: %zu vertices, %zu triangles\n", source, levels,
            m->nv, m->nt);
    // Nine significant digits: the float that glint reads is the one nearest the double midpoint.
    for (size_t i = 0; i < m->nv; i++)
        fprintf(f, "v %.9g %.9g %.9g\n", m->verts[i].p[0], m->verts[i].p[1], m->verts[i].p[2]);
    for (size_t i = 0; i < m->nt; i++)
        fprintf(f, "f %u %u %u\n", m->tris[i].v[0] + 1, m->tris[i].v[1] + 1, m->tris[i].v[2] + 1);
    if (fclose(f) != 0) {
        fprintf(stderr, "subdivide: %s: write error\n", path);
        exit(1);
    }
}

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: subdivide IN.obj OUT.obj LEVELS\n");
        return 2;
    }
    char *end;
    long levels = strtol(argv[3], &end, 10);
    if (*end || levels < 0 || levels > 6) die("LEVELS must be an integer in 0..6");
    meshbuf m = {0};
    read_obj(argv[1], &m);
    if (m.nt == 0) die("no faces in the input");
    size_t in = m.nt;
    for (long i = 0; i < levels; i++) subdivide(&m);
    write_obj(argv[2], &m, argv[1], levels);
    fprintf(stderr, "subdivide: %zu -> %zu triangles, %zu vertices\n", in, m.nt, m.nv);
    free(m.verts);
    free(m.tris);
    return 0;
}
