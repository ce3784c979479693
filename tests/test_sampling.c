// test_sampling.c — chi-square tests of every sampling routine and material scatter against its density,
// and binomial tests of the discrete choices (metal absorption, dielectric reflection, Phong mirror).
#include "check.h"
#include "core/sampling.h"
#include "material/scatter.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI 3.14159265358979323846

// Upper tail probability of the chi-square distribution (Wilson-Hilferty; good to ~1e-3 for dof >= 10).
static double chi2_pvalue(double x, int dof) {
    double k = dof, z = (pow(x / k, 1.0 / 3.0) - (1.0 - 2.0 / (9.0 * k))) / sqrt(2.0 / (9.0 * k));
    return 0.5 * erfc(z / sqrt(2.0));
}

// Chi-square test of observed bin counts against expected probabilities; passes when p >= 1e-3.
static bool chi2_ok(const char *what, const long *obs, const double *prob, int bins, long n) {
    double x = 0.0;
    int dof = -1;
    for (int i = 0; i < bins; i++) {
        double e = prob[i] * (double)n;
        if (e < 5.0) {
            // Too few expected samples for the statistic; any observation here at all is a failure of support.
            if (prob[i] == 0.0 && obs[i] > 0) { fprintf(stderr, "%s: %ld samples in an empty bin %d\n", what, obs[i], i); return false; }
            continue;
        }
        x += ((double)obs[i] - e) * ((double)obs[i] - e) / e;
        dof++;
    }
    double p = chi2_pvalue(x, dof);
    if (p < 1e-3) fprintf(stderr, "%s: chi-square %.1f with %d degrees of freedom, p = %.3g\n", what, x, dof, p);
    return p >= 1e-3;
}

// Binomial test: k successes in n trials with probability p, within 5 standard deviations.
static bool binomial_ok(const char *what, long k, long n, double p) {
    double mean = p * (double)n, sd = sqrt((double)n * p * (1.0 - p));
    bool ok = fabs((double)k - mean) <= 5.0 * sd + 1e-9;
    if (!ok) fprintf(stderr, "%s: %ld of %ld, expected %.1f +- %.1f\n", what, k, n, mean, sd);
    return ok;
}

// A test-local orthonormal frame around unit n (independent of v3_basis): cos(theta) and azimuth of d.
static void local_angles(vec3 n, vec3 d, double *cos_theta, double *phi) {
    vec3 a = fabsf(n.x) < 0.5f ? v3(1, 0, 0) : v3(0, 1, 0);
    vec3 t = v3_unit(v3_cross(n, a)), b = v3_cross(n, t);
    *cos_theta = v3_dot(d, n);
    double p = atan2(v3_dot(d, b), v3_dot(d, t));
    *phi = p < 0 ? p + 2 * PI : p;
}

static int bin_of(double v, double lo, double hi, int n) {
    int i = (int)floor((v - lo) / (hi - lo) * n);
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

enum { NPHI = 16, NR = 12, NBINS = NPHI * NR };

static void test_unit_disk(void) {
    rng r = rng_for_sample(1, 0, 0);
    long obs[NBINS] = {0}, n = 200000, outside = 0;
    double prob[NBINS];
    for (int i = 0; i < NBINS; i++) prob[i] = 1.0 / NBINS;
    for (long i = 0; i < n; i++) {
        float x, y;
        sample_unit_disk(&r, &x, &y);
        double r2 = (double)x * x + (double)y * y, phi = atan2(y, x) + PI;
        if (r2 >= 1.0) outside++;
        // Uniform in the disk: r^2 and the angle are independent and uniform.
        obs[bin_of(r2, 0, 1, NR) * NPHI + bin_of(phi, 0, 2 * PI, NPHI)]++;
    }
    CHECK(outside == 0);
    CHECK(chi2_ok("sample_unit_disk", obs, prob, NBINS, n));
}

static void test_unit_vector(void) {
    rng r = rng_for_sample(2, 0, 0);
    long obs[NBINS] = {0}, n = 200000, bad_len = 0;
    double prob[NBINS];
    for (int i = 0; i < NBINS; i++) prob[i] = 1.0 / NBINS;
    for (long i = 0; i < n; i++) {
        vec3 d = sample_unit_vector(&r);
        if (fabs(v3_len(d) - 1.0) > 1e-5) bad_len++;
        // Uniform on the sphere (Archimedes): z and the azimuth are independent and uniform.
        double phi = atan2(d.y, d.x) + PI;
        obs[bin_of(d.z, -1, 1, NR) * NPHI + bin_of(phi, 0, 2 * PI, NPHI)]++;
    }
    CHECK(bad_len == 0);
    CHECK(chi2_ok("sample_unit_vector", obs, prob, NBINS, n));
}

// sincos_turn against double cos and sin of 2 pi u: every u of the form k / 2^24 near the quarter turns (where
// the reduction switches) and a dense sweep, within 2^-22 absolute; exact at 0 and the quarter turns.
static void test_sincos_turn(void) {
    double worst = 0.0;
    int bad = 0;
    for (long i = 0; i < (1L << 24); i += (i % 4194304 < 64 || i % 4194304 > 4194240) ? 1 : 97) {
        float u = (float)i * 0x1p-24f, c, s;
        sincos_turn(u, &c, &s);
        double a = 2.0 * PI * (double)u, ec = fabs(c - cos(a)), es = fabs(s - sin(a));
        worst = fmax(worst, fmax(ec, es));
        if (ec > 0x1p-22 || es > 0x1p-22) bad++;
    }
    CHECK(bad == 0);
    if (bad) fprintf(stderr, "sincos_turn: worst error %.3g\n", worst);
    const float quarter[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    for (int k = 0; k < 4; k++) {
        float c, s;
        sincos_turn(0.25f * (float)k, &c, &s);
        CHECK(c == quarter[k][0] && s == quarter[k][1]);
    }
}

static void test_sphere_uniform(void) {
    rng r = rng_for_sample(12, 0, 0);
    long obs[NBINS] = {0}, n = 200000, bad_len = 0;
    double prob[NBINS];
    for (int i = 0; i < NBINS; i++) prob[i] = 1.0 / NBINS;
    for (long i = 0; i < n; i++) {
        vec3 d = sample_sphere_uniform(&r);
        if (fabs(v3_len(d) - 1.0) > 1e-6) bad_len++;
        // Uniform on the sphere (Archimedes): z and the azimuth are independent and uniform.
        double phi = atan2(d.y, d.x) + PI;
        obs[bin_of(d.z, -1, 1, NR) * NPHI + bin_of(phi, 0, 2 * PI, NPHI)]++;
    }
    CHECK(bad_len == 0);
    CHECK(chi2_ok("sample_sphere_uniform", obs, prob, NBINS, n));
}

// Bins a cosine-distributed direction about n: cos^2(theta) is uniform (its CDF is cos^2), so is the azimuth.
static void cosine_bin(long *obs, vec3 n, vec3 d, long *below) {
    double c, phi;
    local_angles(n, v3_unit(d), &c, &phi);
    if (c < 0.0) (*below)++;
    obs[bin_of(c * c, 0, 1, NR) * NPHI + bin_of(phi, 0, 2 * PI, NPHI)]++;
}

static const vec3 test_normals[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0.48f, -0.6f, 0.64f}};

static void test_cosine_hemisphere(void) {
    double prob[NBINS];
    for (int i = 0; i < NBINS; i++) prob[i] = 1.0 / NBINS;
    for (size_t k = 0; k < sizeof test_normals / sizeof test_normals[0]; k++) {
        vec3 nrm = v3_unit(test_normals[k]);
        rng r = rng_for_sample(3, k, 0);
        long obs[NBINS] = {0}, n = 100000, below = 0, bad_len = 0;
        for (long i = 0; i < n; i++) {
            vec3 d = sample_cosine_hemisphere(&r, nrm);
            if (fabs(v3_len(d) - 1.0) > 1e-5) bad_len++;
            cosine_bin(obs, nrm, d, &below);
        }
        CHECK(below == 0 && bad_len == 0);
        CHECK(chi2_ok("sample_cosine_hemisphere", obs, prob, NBINS, n));
    }
}

static void test_lambertian(void) {
    double prob[NBINS];
    for (int i = 0; i < NBINS; i++) prob[i] = 1.0 / NBINS;
    material m = material_default(MAT_LAMBERTIAN);
    m.albedo = v3(0.25f, 0.5f, 0.75f);
    for (size_t k = 0; k < sizeof test_normals / sizeof test_normals[0]; k++) {
        vec3 nrm = v3_unit(test_normals[k]);
        vec3 d_in = v3_unit(v3_add(v3_neg(nrm), v3(0.3f, 0.2f, 0.1f)));
        rng r = rng_for_sample(4, k, 0);
        long obs[NBINS] = {0}, n = 100000, below = 0, bad = 0;
        for (long i = 0; i < n; i++) {
            scatter_event ev;
            if (!mat_scatter(&m, m.albedo, d_in, nrm, true, &r, &ev) || !ev.diffuse || fabs(v3_len(ev.dir) - 1.0) > 1e-5 ||
                ev.weight.x != 0.25f || ev.weight.y != 0.5f || ev.weight.z != 0.75f) {
                bad++;
                continue;
            }
            cosine_bin(obs, nrm, ev.dir, &below);
        }
        CHECK(bad == 0 && below == 0);
        CHECK(chi2_ok("lambertian scatter (density cos/pi)", obs, prob, NBINS, n));
    }
    // The fallback: a random unit vector opposite the normal gives the normal, not a zero or NaN direction.
    vec3 nrm = v3_unit(v3(0.48f, -0.6f, 0.64f));
    vec3 d = mat_lambertian_dir(nrm, v3_neg(nrm));
    CHECK(d.x == nrm.x && d.y == nrm.y && d.z == nrm.z);
    d = mat_lambertian_dir(nrm, v3_neg(v3_unit(v3(0.48f, -0.6f, 0.64000005f))));
    CHECK(v3_is_finite(d) && v3_dot(d, nrm) > 0.0f);
}

// P(angle between r + f u and r is <= a) for u uniform on the sphere and fuzz f < 1: the ray at angle a
// meets the sphere of radius f about r at distances rho = cos a +- sqrt(f^2 - sin^2 a), where u.r =
// (rho cos a - 1) / f, and u.r is uniform in [-1, 1].
static double fuzz_cdf(double a, double f) {
    double s = sin(a);
    if (s >= f) return 1.0;
    double q = sqrt(f * f - s * s);
    double cb_far = ((cos(a) + q) * cos(a) - 1.0) / f, cb_near = ((cos(a) - q) * cos(a) - 1.0) / f;
    return (1.0 - cb_far) / 2.0 + (cb_near + 1.0) / 2.0;
}

static void test_metal(void) {
    material m = material_default(MAT_METAL);
    m.albedo = v3(0.7f, 0.6f, 0.5f);
    // Fuzz 0 is a perfect mirror.
    vec3 nrm = v3(0, 1, 0), d_in = v3_unit(v3(1, -1, 0.5f));
    rng r = rng_for_sample(5, 0, 0);
    scatter_event ev = {0};
    CHECK(mat_scatter(&m, m.albedo, d_in, nrm, true, &r, &ev));
    vec3 mirror = v3_reflect(d_in, nrm);
    CHECK(v3_len(v3_sub(ev.dir, mirror)) < 1e-6f && ev.weight.x == 0.7f && ev.weight.z == 0.5f && !ev.diffuse);

    // The fuzz lobe at normal incidence (nothing absorbed): angle from the mirror direction and azimuth.
    const float fuzzes[] = {0.3f, 0.9f};
    for (int k = 0; k < 2; k++) {
        m.fuzz = fuzzes[k];
        double f = m.fuzz, amax = asin(f);
        long obs[NBINS] = {0}, n = 100000, absorbed = 0, outside = 0;
        double prob[NBINS];
        for (int i = 0; i < NR; i++) {
            double p = fuzz_cdf(amax * (i + 1) / NR, f) - fuzz_cdf(amax * i / NR, f);
            for (int j = 0; j < NPHI; j++) prob[i * NPHI + j] = p / NPHI;
        }
        for (long i = 0; i < n; i++) {
            if (!mat_scatter(&m, m.albedo, v3(0, -1, 0), nrm, true, &r, &ev)) { absorbed++; continue; }
            double c, phi;
            local_angles(nrm, ev.dir, &c, &phi);
            double a = acos(fmin(1.0, c));
            if (a > amax + 1e-4) outside++;
            obs[bin_of(a, 0, amax, NR) * NPHI + bin_of(phi, 0, 2 * PI, NPHI)]++;
        }
        CHECK(absorbed == 0 && outside == 0);
        CHECK(chi2_ok("metal fuzz lobe", obs, prob, NBINS, n));
    }

    // Absorption below the surface: with the mirror direction at cos c_r to the normal, the path survives
    // when c_r + f u.n > 0, probability 1 - (1 - c_r / f) / 2.
    m.fuzz = 0.8f;
    double c_r = 0.3;
    vec3 d_graze = v3((float)sqrt(1 - c_r * c_r), (float)-c_r, 0);
    long kept = 0, n = 200000;
    for (long i = 0; i < n; i++)
        if (mat_scatter(&m, m.albedo, d_graze, nrm, true, &r, &ev)) {
            kept++;
            if (!(v3_dot(ev.dir, nrm) > 0.0f)) kept = -n; // a surviving direction below the surface fails
        }
    CHECK(binomial_ok("metal survival at grazing incidence", kept, n, 1.0 - (1.0 - c_r / 0.8) / 2.0));
}

// Schlick's reflectance computed independently in double: r0 + (1 - r0)(1 - cos)^5.
static double schlick_ref(double c, double ior) {
    double r0 = (1.0 - ior) / (1.0 + ior);
    r0 *= r0;
    return r0 + (1.0 - r0) * pow(1.0 - c, 5.0);
}

static void test_dielectric(void) {
    material m = material_default(MAT_DIELECTRIC);
    m.ior = 1.5f;
    vec3 nrm = v3(0, 0, 1);
    rng r = rng_for_sample(6, 0, 0);
    // (cos of incidence, arriving on the front side?)
    const struct { double c; bool front; } cases[] = {{1.0, true}, {0.9, true}, {0.5, true}, {0.2, true},
                                                      {0.05, true}, {0.95, false}, {0.8, false}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        double c = cases[k].c, s = sqrt(1 - c * c);
        vec3 d = v3((float)s, 0, (float)-c);
        double eta = cases[k].front ? 1.0 / 1.5 : 1.5;
        long refl = 0, n = 200000, bad = 0;
        for (long i = 0; i < n; i++) {
            scatter_event ev;
            if (!mat_scatter(&m, m.albedo, d, nrm, cases[k].front, &r, &ev) || ev.weight.x != 1.0f) { bad++; continue; }
            if (ev.dir.z > 0) {
                refl++;
                if (v3_len(v3_sub(ev.dir, v3_reflect(d, nrm))) > 1e-6f) bad++;
            } else {
                // Snell: eta sin(theta_i) = sin(theta_t), in the plane of incidence.
                double st = sqrt((double)ev.dir.x * ev.dir.x + (double)ev.dir.y * ev.dir.y);
                if (fabs(st - eta * s) > 1e-5 || fabs(ev.dir.y) > 1e-6 || ev.dir.x < 0) bad++;
            }
        }
        CHECK(bad == 0);
        CHECK(binomial_ok("dielectric reflection probability (Schlick)", refl, n, schlick_ref(c, 1.5)));
    }
    // Total internal reflection: from inside at sin(theta) > 1/1.5 every ray reflects.
    vec3 d = v3(0.8f, 0, -0.6f);
    long refl = 0, n = 10000;
    for (long i = 0; i < n; i++) {
        scatter_event ev;
        if (mat_scatter(&m, m.albedo, d, nrm, false, &r, &ev) && ev.dir.z > 0) refl++;
    }
    CHECK(refl == n);
    CHECK_NEAR(mat_dielectric_reflectance(0.6f, 1.5f), 1.0, 0);
    CHECK_NEAR(mat_dielectric_reflectance(1.0f, 1.0f / 1.5f), 0.04, 1e-6);
}

static void test_phong(void) {
    material m = material_default(MAT_PHONG);
    m.albedo = v3(0.2f, 0.4f, 0.6f);
    m.reflective = 0.3f;
    vec3 nrm = v3(0, 1, 0), d = v3_unit(v3(1, -2, 0));
    rng r = rng_for_sample(7, 0, 0);
    long mirror = 0, n = 100000, bad = 0;
    for (long i = 0; i < n; i++) {
        scatter_event ev;
        if (!mat_scatter(&m, m.albedo, d, nrm, true, &r, &ev)) { bad++; continue; }
        if (!ev.diffuse) {
            mirror++;
            if (v3_len(v3_sub(ev.dir, v3_reflect(d, nrm))) > 1e-6f || ev.weight.x != 1.0f) bad++;
        } else if (ev.weight.y != 0.4f || !(ev.dir.y > 0)) {
            bad++;
        }
    }
    CHECK(bad == 0);
    CHECK(binomial_ok("phong mirror probability", mirror, n, 0.3));
}

static void test_emitter(void) {
    material m = material_default(MAT_DIFFUSE_LIGHT);
    m.emission = v3(2, 3, 4);
    rng r = rng_for_sample(8, 0, 0);
    scatter_event ev;
    CHECK(!mat_scatter(&m, m.albedo, v3(0, -1, 0), v3(0, 1, 0), true, &r, &ev));
    vec3 p = v3s(0.0f);
    CHECK(mat_emitted(&m, NULL, true, 0, 0, p).y == 3.0f && mat_emitted(&m, NULL, false, 0, 0, p).y == 0.0f);
    m.two_sided = true;
    CHECK(mat_emitted(&m, NULL, false, 0, 0, p).z == 4.0f);
    material lam = material_default(MAT_LAMBERTIAN);
    CHECK(mat_emitted(&lam, NULL, true, 0, 0, p).x == 0.0f);
}

// Textures: the albedo texture replaces `albedo` (a checker gives each region its colour, and the scatter
// weight follows), the emission texture multiplies `emission`; materials without textures never look one up.
static void test_textured_materials(void) {
    texture tex[2] = {texture_checker(1.0f, v3(0.2f, 0.4f, 0.6f), v3(0.9f, 0.8f, 0.7f)), texture_solid(v3(0.5f, 1.0f, 2.0f))};
    material m = material_default(MAT_LAMBERTIAN);
    m.albedo = v3s(0.3f);
    CHECK(mat_albedo(&m, NULL, 0.5f, 0.5f, v3(0.5f, 0.5f, 0.5f)).x == 0.3f);
    m.albedo_texture = 0;
    vec3 even = mat_albedo(&m, tex, 0, 0, v3(0.5f, 0.5f, 0.5f)), odd = mat_albedo(&m, tex, 0, 0, v3(1.5f, 0.5f, 0.5f));
    CHECK(even.x == 0.2f && even.y == 0.4f && even.z == 0.6f);
    CHECK(odd.x == 0.9f && odd.y == 0.8f && odd.z == 0.7f);
    rng r = rng_for_sample(9, 0, 0);
    scatter_event ev;
    CHECK(mat_scatter(&m, odd, v3(0, -1, 0), v3(0, 1, 0), true, &r, &ev) && ev.weight.y == 0.8f);
    material l = material_default(MAT_DIFFUSE_LIGHT);
    l.emission = v3s(4.0f);
    l.emission_texture = 1;
    vec3 e = mat_emitted(&l, tex, true, 0, 0, v3s(0.0f));
    CHECK(e.x == 2.0f && e.y == 4.0f && e.z == 8.0f);
    CHECK(mat_emitted(&l, tex, false, 0, 0, v3s(0.0f)).x == 0.0f);
    // Dielectric events say whether they crossed the surface.
    material g = material_default(MAT_DIELECTRIC);
    long crossed = 0, n = 20000;
    for (long i = 0; i < n; i++)
        if (mat_scatter(&g, g.albedo, v3(0, 0, -1), v3(0, 0, 1), true, &r, &ev) && ev.transmitted == (ev.dir.z < 0))
            crossed += ev.transmitted;
        else
            crossed = -n;
    CHECK(binomial_ok("dielectric transmission at normal incidence", crossed, n, 0.96));
}

int main(void) {
    test_unit_disk();
    test_unit_vector();
    test_sincos_turn();
    test_sphere_uniform();
    test_cosine_hemisphere();
    test_lambertian();
    test_metal();
    test_dielectric();
    test_phong();
    test_emitter();
    test_textured_materials();
    return check_summary();
}
