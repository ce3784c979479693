// tri_split.c — cutting long, slanted triangles into pieces with boxes of their own (tri_split.h). The clipping
// is in double, where the vertices are exact and each cut point is off by far less than a float's rounding, and
// the pieces' bounds are rounded outwards: the build pads them further for the slab test.
#include "accel/tri_split.h"

#include <math.h>

// A triangle's box half area (dx dy + dy dz + dz dx) against its area: halve it once above the first ratio,
// twice above the second, three times above the third. At their worst orientation an equilateral triangle reaches
// 4.6, a right isosceles one 5.2, a right one with legs 1:2 6.5 (and 1:4 10.2): well-shaped triangles stay whole.
static const double SPLIT_RATIO[TRI_SPLIT_MAX_LEVELS] = {8.0, 32.0, 128.0};


int tri_split_levels(vec3 p0, vec3 p1, vec3 p2) {
    double e1[3] = {(double)p1.x - p0.x, (double)p1.y - p0.y, (double)p1.z - p0.z};
    double e2[3] = {(double)p2.x - p0.x, (double)p2.y - p0.y, (double)p2.z - p0.z};
    double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
    double area2 = 0.25 * (cx * cx + cy * cy + cz * cz); // the squared area: no square root per triangle
    double lo[3] = {p0.x, p0.y, p0.z}, hi[3] = {p0.x, p0.y, p0.z};
    const vec3 q[2] = {p1, p2};
    for (int i = 0; i < 2; i++) {
        const double c[3] = {q[i].x, q[i].y, q[i].z};
        for (int a = 0; a < 3; a++) {
            if (c[a] < lo[a]) lo[a] = c[a];
            if (c[a] > hi[a]) hi[a] = c[a];
        }
    }
    double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    double half_area = dx * dy + dy * dz + dz * dx;
    if (!(area2 > 0.0) || !isfinite(half_area) || !isfinite(area2)) return 0; // degenerate: nothing to gain
    int levels = 0;
    while (levels < TRI_SPLIT_MAX_LEVELS && half_area * half_area > SPLIT_RATIO[levels] * SPLIT_RATIO[levels] * area2)
        levels++;
    return levels;
}

bool tri_split_mesh_wants(const mesh *m) {
    size_t n = m->triangle_count, step = n > TRI_SPLIT_SAMPLES ? n / TRI_SPLIT_SAMPLES : 1, seen = 0, asking = 0;
    for (size_t k = 0; k < n && seen < TRI_SPLIT_SAMPLES; k += step, seen++) {
        vec3 p0, p1, p2;
        mesh_triangle_positions(m, k, &p0, &p1, &p2);
        asking += tri_split_levels(p0, p1, p2) > 0;
    }
    return seen > 0 && 2 * asking >= seen;
}

enum { MAX_POLY = 3 + 6 }; // a triangle clipped by six planes gains at most one corner per plane

// Clips polygon in[0, n) to the side of plane x[axis] = at where x[axis] <= at (keep_below) or >= at, into out;
// returns the new corner count. Cut points lie exactly on the plane.
static int clip_plane(const double (*in)[3], int n, int axis, double at, bool keep_below, double (*out)[3]) {
    int m = 0;
    for (int i = 0; i < n; i++) {
        const double *a = in[i], *b = in[(i + 1) % n];
        bool a_in = keep_below ? a[axis] <= at : a[axis] >= at;
        bool b_in = keep_below ? b[axis] <= at : b[axis] >= at;
        if (a_in) {
            for (int k = 0; k < 3; k++) out[m][k] = a[k];
            m++;
        }
        if (a_in != b_in) { // the edge crosses the plane: its cut point
            double t = (at - a[axis]) / (b[axis] - a[axis]);
            for (int k = 0; k < 3; k++) out[m][k] = a[k] + t * (b[k] - a[k]);
            out[m][axis] = at;
            m++;
        }
    }
    return m;
}

// The float box holding every double in [lo, hi] per axis.
static bounds3 bounds_outward(const double lo[3], const double hi[3]) {
    float l[3], h[3];
    for (int a = 0; a < 3; a++) {
        l[a] = (float)lo[a];
        if ((double)l[a] > lo[a]) l[a] = nextafterf(l[a], -INFINITY);
        h[a] = (float)hi[a];
        if ((double)h[a] < hi[a]) h[a] = nextafterf(h[a], INFINITY);
    }
    return (bounds3){v3(l[0], l[1], l[2]), v3(h[0], h[1], h[2])};
}

// The part of triangle tri inside the box [lo, hi] (infinite planes ignored), cut `levels` more times; writes its
// pieces' bounds into out and returns how many.
static int split_piece(const double (*tri)[3], const double lo[3], const double hi[3], int levels, bounds3 *out) {
    double a[MAX_POLY][3], b[MAX_POLY][3];
    int n = 3;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) a[i][k] = tri[i][k];
    double (*cur)[3] = a, (*next)[3] = b;
    for (int axis = 0; axis < 3 && n > 0; axis++) {
        if (isfinite(lo[axis])) {
            n = clip_plane((const double (*)[3])cur, n, axis, lo[axis], false, next);
            double (*t)[3] = cur;
            cur = next;
            next = t;
        }
        if (n > 0 && isfinite(hi[axis])) {
            n = clip_plane((const double (*)[3])cur, n, axis, hi[axis], true, next);
            double (*t)[3] = cur;
            cur = next;
            next = t;
        }
    }
    if (n == 0) return 0;
    double blo[3] = {cur[0][0], cur[0][1], cur[0][2]}, bhi[3] = {cur[0][0], cur[0][1], cur[0][2]};
    for (int i = 1; i < n; i++)
        for (int k = 0; k < 3; k++) {
            if (cur[i][k] < blo[k]) blo[k] = cur[i][k];
            if (cur[i][k] > bhi[k]) bhi[k] = cur[i][k];
        }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (bhi[k] - blo[k] > bhi[axis] - blo[axis]) axis = k;
    double mid = 0.5 * (blo[axis] + bhi[axis]);
    if (levels == 0 || !(mid > blo[axis] && mid < bhi[axis])) {
        out[0] = bounds_outward(blo, bhi);
        return 1;
    }
    // Both halves share the plane at mid exactly: every point of the piece lies in one of them.
    double left_hi[3] = {hi[0], hi[1], hi[2]}, right_lo[3] = {lo[0], lo[1], lo[2]};
    left_hi[axis] = mid;
    right_lo[axis] = mid;
    int count = split_piece(tri, lo, left_hi, levels - 1, out);
    return count + split_piece(tri, right_lo, hi, levels - 1, out + count);
}

int tri_split_bounds(vec3 p0, vec3 p1, vec3 p2, int levels, bounds3 *out) {
    const double tri[3][3] = {{p0.x, p0.y, p0.z}, {p1.x, p1.y, p1.z}, {p2.x, p2.y, p2.z}};
    const double lo[3] = {-INFINITY, -INFINITY, -INFINITY}, hi[3] = {INFINITY, INFINITY, INFINITY};
    return split_piece(tri, lo, hi, levels, out);
}

bool tri_clip_bounds(vec3 p0, vec3 p1, vec3 p2, const float lo[3], const float hi[3], bounds3 *out) {
    const double tri[3][3] = {{p0.x, p0.y, p0.z}, {p1.x, p1.y, p1.z}, {p2.x, p2.y, p2.z}};
    const double l[3] = {lo[0], lo[1], lo[2]}, h[3] = {hi[0], hi[1], hi[2]};
    return split_piece(tri, l, h, 0, out) == 1;
}
