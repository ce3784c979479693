// mesh_io.c — OBJ reading and writing for the benchmark's mesh tools (see mesh_io.h).
#include "mesh_io.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *tool = "mesh";

void mesh_tool_name(const char *name) { tool = name; }

_Noreturn void mesh_die(const char *what) {
    fprintf(stderr, "%s: %s\n", tool, what);
    exit(1);
}

static void *grow(void *p, size_t *cap, size_t need, size_t size) {
    if (need <= *cap) return p;
    size_t c = *cap ? *cap : 1024;
    while (c < need) c *= 2;
    void *q = realloc(p, c * size);
    if (!q) mesh_die("out of memory");
    *cap = c;
    return q;
}

uint32_t mesh_add_vertex(meshbuf *m, const double p[3]) {
    if (m->nv >= UINT32_MAX) mesh_die("too many vertices");
    m->verts = grow(m->verts, &m->capv, m->nv + 1, sizeof *m->verts);
    memcpy(m->verts[m->nv].p, p, sizeof m->verts[0].p);
    return (uint32_t)m->nv++;
}

void mesh_add_tri(meshbuf *m, uint32_t a, uint32_t b, uint32_t c) {
    m->tris = grow(m->tris, &m->capt, m->nt + 1, sizeof *m->tris);
    m->tris[m->nt++] = (mesh_tri){{a, b, c}};
}

// The vertex index of an OBJ face corner ("7", "7/2", "7//3", "-1/2/3"): 1-based, or negative from the end.
static uint32_t corner_index(const char *tok, size_t nv, const char *path, long line) {
    char *end;
    errno = 0;
    long i = strtol(tok, &end, 10);
    if (end == tok || errno || (*end && *end != '/')) {
        fprintf(stderr, "%s: %s:%ld: bad face corner '%s'\n", tool, path, line, tok);
        exit(1);
    }
    long k = i > 0 ? i - 1 : (long)nv + i;
    if (i == 0 || k < 0 || (size_t)k >= nv) {
        fprintf(stderr, "%s: %s:%ld: vertex index %ld out of range\n", tool, path, line, i);
        exit(1);
    }
    return (uint32_t)k;
}

void mesh_read_obj(const char *path, meshbuf *m) {
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "%s: %s: %s\n", tool, path, strerror(errno));
        exit(1);
    }
    char line[4096];
    long n = 0;
    while (fgets(line, sizeof line, f)) {
        n++;
        if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
            double p[3];
            if (sscanf(line + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) != 3) {
                fprintf(stderr, "%s: %s:%ld: expected three coordinates\n", tool, path, n);
                exit(1);
            }
            mesh_add_vertex(m, p);
        } else if (line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
            uint32_t first = 0, prev = 0;
            int k = 0;
            char *save = NULL;
            for (char *tok = strtok_r(line + 2, " \t\r\n", &save); tok; tok = strtok_r(NULL, " \t\r\n", &save)) {
                if (tok[0] == '#') break;
                uint32_t v = corner_index(tok, m->nv, path, n);
                if (k == 0) first = v;
                else if (k >= 2) mesh_add_tri(m, first, prev, v);
                prev = v;
                k++;
            }
        }
    }
    if (ferror(f)) mesh_die("read error");
    fclose(f);
}

void mesh_write_obj(const char *path, const meshbuf *m, const char *header) {
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "%s: %s: %s\n", tool, path, strerror(errno));
        exit(1);
    }
    // bench/run.sh reads the triangle count from the end of this first line
    fprintf(f, "# %s: %zu vertices, %zu triangles\n", header, m->nv, m->nt);
    // Nine significant digits: the float that glint reads is the one nearest the double written.
    for (size_t i = 0; i < m->nv; i++)
        fprintf(f, "v %.9g %.9g %.9g\n", m->verts[i].p[0], m->verts[i].p[1], m->verts[i].p[2]);
    for (size_t i = 0; i < m->nt; i++)
        fprintf(f, "f %u %u %u\n", m->tris[i].v[0] + 1, m->tris[i].v[1] + 1, m->tris[i].v[2] + 1);
    if (ferror(f) | (fclose(f) != 0)) { // both, so that the file is closed either way
        fprintf(stderr, "%s: %s: write error\n", tool, path);
        exit(1);
    }
}

uint64_t mesh_hash64(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    return x ^ (x >> 33);
}

void mesh_free(meshbuf *m) {
    free(m->verts);
    free(m->tris);
    *m = (meshbuf){0};
}
