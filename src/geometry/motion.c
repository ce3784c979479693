// motion.c — transforms that move between two poses: decomposition into translation, rotation and stretch
// (Shoemake and Duff's polar decomposition, as pbrt's AnimatedTransform), interpolation at a time, and a box
// that holds the whole sweep.
#include "geometry/motion.h"

#include <math.h>
#include <string.h>

// The 3x3 determinant.
static double det3(double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

// The inverse of a 3x3 matrix by cofactors; false when singular.
static bool inv3(double a[3][3], double out[3][3]) {
    double d = det3(a);
    if (!(d != 0.0) || !isfinite(d)) return false;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            // cofactor of a[j][i], for the transpose of the cofactor matrix
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            out[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / d;
        }
    return true;
}

// A unit quaternion (x, y, z, w) from a proper rotation matrix (Shepperd's method: the largest diagonal term
// chooses the stable formula).
static void quat_from_matrix(double r[3][3], double q[4]) {
    double tr = r[0][0] + r[1][1] + r[2][2];
    if (tr > 0.0) {
        double s = 2.0 * sqrt(tr + 1.0);
        q[3] = 0.25 * s;
        q[0] = (r[2][1] - r[1][2]) / s;
        q[1] = (r[0][2] - r[2][0]) / s;
        q[2] = (r[1][0] - r[0][1]) / s;
    } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
        double s = 2.0 * sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]);
        q[3] = (r[2][1] - r[1][2]) / s;
        q[0] = 0.25 * s;
        q[1] = (r[0][1] + r[1][0]) / s;
        q[2] = (r[0][2] + r[2][0]) / s;
    } else if (r[1][1] > r[2][2]) {
        double s = 2.0 * sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]);
        q[3] = (r[0][2] - r[2][0]) / s;
        q[0] = (r[0][1] + r[1][0]) / s;
        q[1] = 0.25 * s;
        q[2] = (r[1][2] + r[2][1]) / s;
    } else {
        double s = 2.0 * sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]);
        q[3] = (r[1][0] - r[0][1]) / s;
        q[0] = (r[0][2] + r[2][0]) / s;
        q[1] = (r[1][2] + r[2][1]) / s;
        q[2] = 0.25 * s;
    }
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; k++) q[k] /= n;
}

// The rotation matrix of a unit quaternion.
static void matrix_from_quat(const double q[4], double r[3][3]) {
    double x = q[0], y = q[1], z = q[2], w = q[3];
    r[0][0] = 1 - 2 * (y * y + z * z), r[0][1] = 2 * (x * y - z * w), r[0][2] = 2 * (x * z + y * w);
    r[1][0] = 2 * (x * y + z * w), r[1][1] = 1 - 2 * (x * x + z * z), r[1][2] = 2 * (y * z - x * w);
    r[2][0] = 2 * (x * z - y * w), r[2][1] = 2 * (y * z + x * w), r[2][2] = 1 - 2 * (x * x + y * y);
}

// M = T R S: the translation column, then the polar decomposition of the linear part, L = R S, by the
// iteration R <- (R + R^-T) / 2, which converges to the orthogonal factor; a mirror (det R = -1) is moved
// into S (R S = (-R)(-S)) so that R is a rotation a quaternion can hold.
static bool decompose(const mat4 *m, motion_pose *p) {
    if (!mat4_is_affine(m)) return false;
    double l[3][3], r[3][3];
    for (int i = 0; i < 3; i++) {
        p->t[i] = m->m[i][3];
        for (int j = 0; j < 3; j++) l[i][j] = r[i][j] = m->m[i][j];
    }
    if (!(fabs(det3(l)) > 0.0)) return false;
    for (int iter = 0; iter < 100; iter++) {
        double inv[3][3], next[3][3], change = 0.0;
        if (!inv3(r, inv)) return false;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                next[i][j] = 0.5 * (r[i][j] + inv[j][i]);
                change = fmax(change, fabs(next[i][j] - r[i][j]));
            }
        memcpy(r, next, sizeof r);
        if (change < 1e-14) break;
    }
    double sign = det3(r) < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) r[i][j] *= sign;
    // S = R^T L (R orthogonal), symmetrised against rounding.
    double s[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double acc = 0.0;
            for (int k = 0; k < 3; k++) acc += r[k][i] * l[k][j];
            s[i][j] = acc;
        }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) p->s[i][j] = 0.5 * (s[i][j] + s[j][i]);
    quat_from_matrix(r, p->q);
    return true;
}

bool motion_make(const mat4 *m0, const mat4 *m1, motion *out) {
    motion mo;
    if (!decompose(m0, &mo.p0) || !decompose(m1, &mo.p1)) return false;
    if ((det3(mo.p0.s) < 0.0) != (det3(mo.p1.s) < 0.0)) return false;
    double dot = 0.0;
    for (int k = 0; k < 4; k++) dot += mo.p0.q[k] * mo.p1.q[k];
    if (dot < 0.0) { // q and -q are the same rotation: take the one on q0's side, for the shorter arc
        for (int k = 0; k < 4; k++) mo.p1.q[k] = -mo.p1.q[k];
        dot = -dot;
    }
    mo.theta = acos(fmin(1.0, dot));
    *out = mo;
    return true;
}

// The pose at time t: translation and stretch interpolated linearly, the rotation by slerp.
static void pose_at(const motion *m, double t, double tr[3], double r[3][3], double s[3][3]) {
    for (int i = 0; i < 3; i++) {
        tr[i] = m->p0.t[i] + t * (m->p1.t[i] - m->p0.t[i]);
        for (int j = 0; j < 3; j++) s[i][j] = m->p0.s[i][j] + t * (m->p1.s[i][j] - m->p0.s[i][j]);
    }
    double w0 = 1.0 - t, w1 = t, q[4];
    if (m->theta > 1e-6) { // slerp; for nearly equal rotations the normalised lerp is as exact
        double st = sin(m->theta);
        w0 = sin((1.0 - t) * m->theta) / st;
        w1 = sin(t * m->theta) / st;
    }
    double n = 0.0;
    for (int k = 0; k < 4; k++) {
        q[k] = w0 * m->p0.q[k] + w1 * m->p1.q[k];
        n += q[k] * q[k];
    }
    n = sqrt(n);
    for (int k = 0; k < 4; k++) q[k] /= n;
    matrix_from_quat(q, r);
}

void motion_at(const motion *m, float t, transform *out) {
    double tr[3], r[3][3], s[3][3], sinv[3][3];
    pose_at(m, (double)t, tr, r, s);
    // A stretch between two of one sign is definite (a convex combination), so it has an inverse.
    if (!inv3(s, sinv)) memset(sinv, 0, sizeof sinv);
    double l[3][3], linv[3][3]; // L = R S and L^-1 = S^-1 R^T
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double a = 0.0, b = 0.0;
            for (int k = 0; k < 3; k++) {
                a += r[i][k] * s[k][j];
                b += sinv[i][k] * r[j][k];
            }
            l[i][j] = a;
            linv[i][j] = b;
        }
    out->m = mat4_identity();
    out->inv = mat4_identity();
    for (int i = 0; i < 3; i++) {
        double ti = 0.0;
        for (int j = 0; j < 3; j++) {
            out->m.m[i][j] = (float)l[i][j];
            out->inv.m[i][j] = (float)linv[i][j];
            ti -= linv[i][j] * tr[j];
        }
        out->m.m[i][3] = (float)tr[i];
        out->inv.m[i][3] = (float)ti;
    }
}

// The Frobenius norm of a 3x3 matrix: at least its largest stretch of a vector.
static double frobenius(const double *a) {
    double s = 0.0;
    for (int i = 0; i < 9; i++) s += a[i] * a[i];
    return sqrt(s);
}

enum { MOTION_BOUND_STEPS = 64 };

bounds3 motion_bounds(const motion *m, bounds3 b, float t0, float t1) {
    bounds3 out = bounds3_empty();
    if (bounds3_is_empty(b)) return out;
    // rho bounds |p| over the box: the farthest corner from the origin.
    double rho = 0.0;
    for (int c = 0; c < 8; c++) {
        double x = (c & 1) ? b.hi.x : b.lo.x, y = (c & 2) ? b.hi.y : b.lo.y, z = (c & 4) ? b.hi.z : b.lo.z;
        rho = fmax(rho, sqrt(x * x + y * y + z * z));
    }
    // Speed of any point M(t) p: |T1 - T0| + |R'(t) S(t) p| + |R(t) (S1 - S0) p|, the rotation turning at the
    // constant rate 2 theta, and |S(t)| at most the larger of |S0| and |S1| (a norm is convex).
    double dt[3], ds[3][3], tmax = 0.0;
    for (int i = 0; i < 3; i++) {
        dt[i] = m->p1.t[i] - m->p0.t[i];
        tmax = fmax(tmax, fmax(fabs(m->p0.t[i]), fabs(m->p1.t[i])));
        for (int j = 0; j < 3; j++) ds[i][j] = m->p1.s[i][j] - m->p0.s[i][j];
    }
    double smax = fmax(frobenius(&m->p0.s[0][0]), frobenius(&m->p1.s[0][0]));
    double speed = sqrt(dt[0] * dt[0] + dt[1] * dt[1] + dt[2] * dt[2]) + (2.0 * m->theta * smax + frobenius(&ds[0][0])) * rho;
    int steps = t1 > t0 ? MOTION_BOUND_STEPS : 0;
    double h = steps ? ((double)t1 - (double)t0) / steps : 0.0;
    // Half a step of travel, plus the float rounding of the matrices motion_at makes (a few ulps of each term).
    double pad = speed * 0.5 * h + (smax * rho + tmax) * 0x1p-19;
    for (int i = 0; i <= steps; i++) {
        float t = i == steps ? t1 : (float)((double)t0 + h * i);
        transform xf;
        motion_at(m, t, &xf);
        out = bounds3_union(out, mat4_apply_bounds(&xf.m, b));
    }
    vec3 p = v3s((float)pad);
    // Rounded outwards: the pad is added in float to coordinates that may be far larger.
    out.lo = v3_sub(out.lo, p);
    out.hi = v3_add(out.hi, p);
    out.lo = v3(nextafterf(out.lo.x, -INFINITY), nextafterf(out.lo.y, -INFINITY), nextafterf(out.lo.z, -INFINITY));
    out.hi = v3(nextafterf(out.hi.x, INFINITY), nextafterf(out.hi.y, INFINITY), nextafterf(out.hi.z, INFINITY));
    return out;
}
