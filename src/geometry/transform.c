// transform.c — building, composing and inverting affine 4x4 matrices, and transforming bounding boxes.
#include "geometry/transform.h"

#include <math.h>

mat4 mat4_identity(void) {
    mat4 r = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    return r;
}

mat4 mat4_translate(vec3 t) {
    mat4 r = mat4_identity();
    r.m[0][3] = t.x;
    r.m[1][3] = t.y;
    r.m[2][3] = t.z;
    return r;
}

mat4 mat4_scale(vec3 s) {
    mat4 r = mat4_identity();
    r.m[0][0] = s.x;
    r.m[1][1] = s.y;
    r.m[2][2] = s.z;
    return r;
}

// sin and cos of an angle in degrees, exact at multiples of 90 so that quarter turns keep boxes axis-aligned.
static void sin_cos_degrees(double degrees, double *s, double *c) {
    double r = fmod(degrees, 360.0);
    if (r < 0) r += 360.0;
    if (r == 0.0) { *s = 0; *c = 1; return; }
    if (r == 90.0) { *s = 1; *c = 0; return; }
    if (r == 180.0) { *s = 0; *c = -1; return; }
    if (r == 270.0) { *s = -1; *c = 0; return; }
    double rad = r * (3.14159265358979323846 / 180.0);
    *s = sin(rad);
    *c = cos(rad);
}

mat4 mat4_rotate(vec3 axis, float degrees) {
    double x = axis.x, y = axis.y, z = axis.z;
    double len = sqrt(x * x + y * y + z * z);
    if (!(len > 0.0) || !isfinite(len) || !isfinite(degrees)) return mat4_identity();
    x /= len;
    y /= len;
    z /= len;
    double s, c;
    sin_cos_degrees(degrees, &s, &c);
    double k = 1.0 - c;
    // Rodrigues' formula: R = cI + s[a]x + (1 - c) a a^T.
    double r[3][3] = {
        {c + x * x * k, x * y * k - z * s, x * z * k + y * s},
        {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
        {z * x * k - y * s, z * y * k + x * s, c + z * z * k},
    };
    mat4 out = mat4_identity();
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) out.m[i][j] = (float)r[i][j];
    return out;
}

mat4 mat4_mul(const mat4 *a, const mat4 *b) {
    mat4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            // Accumulate in double: composing many transforms should not drift.
            double acc = 0.0;
            for (int k = 0; k < 4; k++) acc += (double)a->m[i][k] * (double)b->m[k][j];
            r.m[i][j] = (float)acc;
        }
    return r;
}

mat4 mat4_transpose(const mat4 *a) {
    mat4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) r.m[i][j] = a->m[j][i];
    return r;
}

bool mat4_is_affine(const mat4 *a) {
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            if (!isfinite(a->m[i][j])) return false;
    return a->m[3][0] == 0.0f && a->m[3][1] == 0.0f && a->m[3][2] == 0.0f && a->m[3][3] == 1.0f;
}

bool mat4_invert(const mat4 *a, mat4 *out) {
    if (!mat4_is_affine(a)) return false;
    double m[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) m[i][j] = a->m[i][j];
    // Inverse of the linear part by the adjugate: inv = adj(A) / det(A).
    double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    if (det == 0.0 || !isfinite(det)) return false;
    double id = 1.0 / det;
    double inv[3][3] = {
        {c00 * id, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id, (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id},
        {c01 * id, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id, (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id},
        {c02 * id, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id, (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id},
    };
    mat4 r = mat4_identity();
    for (int i = 0; i < 3; i++) {
        // The translation of the inverse is -inv(A) t.
        double t = 0.0;
        for (int j = 0; j < 3; j++) {
            if (!isfinite((float)inv[i][j])) return false;
            r.m[i][j] = (float)inv[i][j];
            t -= inv[i][j] * (double)a->m[j][3];
        }
        if (!isfinite((float)t)) return false;
        r.m[i][3] = (float)t;
    }
    *out = r;
    return true;
}

bounds3 mat4_apply_bounds(const mat4 *a, bounds3 b) {
    if (bounds3_is_empty(b)) return b;
    float lo[3], hi[3];
    double blo[3] = {b.lo.x, b.lo.y, b.lo.z}, bhi[3] = {b.hi.x, b.hi.y, b.hi.z};
    for (int i = 0; i < 3; i++) {
        // Each output coordinate is a sum of terms m_ij x_j: its extremes take each term's own extreme.
        double l = a->m[i][3], h = a->m[i][3], mag = fabs(a->m[i][3]);
        for (int j = 0; j < 3; j++) {
            double e = a->m[i][j] * blo[j], f = a->m[i][j] * bhi[j];
            l += fmin(e, f);
            h += fmax(e, f);
            mag += fmax(fabs(e), fabs(f));
        }
        // mat4_apply_point rounds six times in float, each error at most 2^-24 of the terms' magnitude sum:
        // pad by more than that so that float-transformed points stay inside even when the terms cancel.
        double pad = mag * 0x1p-21;
        lo[i] = nextafterf((float)(l - pad), -INFINITY);
        hi[i] = nextafterf((float)(h + pad), INFINITY);
    }
    return (bounds3){v3(lo[0], lo[1], lo[2]), v3(hi[0], hi[1], hi[2])};
}

double mat4_linear_det(const mat4 *a) {
    const float(*m)[4] = a->m;
    return (double)m[0][0] * ((double)m[1][1] * m[2][2] - (double)m[1][2] * m[2][1]) -
           (double)m[0][1] * ((double)m[1][0] * m[2][2] - (double)m[1][2] * m[2][0]) +
           (double)m[0][2] * ((double)m[1][0] * m[2][1] - (double)m[1][1] * m[2][0]);
}

bool mat4_similarity_scale(const mat4 *a, double *scale) {
    double c[3][3]; // the columns: the images of the axes
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) c[j][i] = a->m[i][j];
    double n[3], d[3];
    for (int j = 0; j < 3; j++) n[j] = c[j][0] * c[j][0] + c[j][1] * c[j][1] + c[j][2] * c[j][2];
    for (int j = 0; j < 3; j++) {
        const double *x = c[j], *y = c[(j + 1) % 3];
        d[j] = x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    }
    // Columns of equal length, pairwise orthogonal, up to the float rounding of a composed rotation.
    double tol = 1e-5 * n[0];
    for (int j = 0; j < 3; j++)
        if (fabs(n[j] - n[0]) > tol || fabs(d[j]) > tol) return false;
    *scale = sqrt((n[0] + n[1] + n[2]) / 3.0);
    return true;
}

bool transform_make(const mat4 *m, transform *out) {
    mat4 inv;
    if (!mat4_invert(m, &inv)) return false;
    out->m = *m;
    out->inv = inv;
    return true;
}

transform transform_identity(void) {
    transform t = {mat4_identity(), mat4_identity()};
    return t;
}

transform transform_compose(const transform *a, const transform *b) {
    transform t;
    t.m = mat4_mul(&a->m, &b->m);
    t.inv = mat4_mul(&b->inv, &a->inv);
    return t;
}
