// test_bsdf.c — the BSDF interface (material/bsdf.h): white-furnace energy of every microfacet material with and
// without energy compensation, a chi-square goodness-of-fit test of every sampling routine against its own
// bsdf_pdf (as Mitsuba 3's test suite: (theta, phi) histogram, expected counts by adaptive Simpson integration of
// the pdf, bins with expected < 5 pooled, Pearson chi-square, significance 0.01 after Sidak's correction),
// reciprocity, sample weights against f cos / pdf, and the book's materials through the interface. It prints
// the furnace figures and the chi-square table.
#include "check.h"
#include "material/bsdf.h"
#include "material/microfacet.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

// A bsdf of material m facing +z (tangent +x) on its outward side (front) or inside.
static bsdf make(const material *m, bool front, bool compensate) {
    bsdf_site site = {v3(0, 0, 1), v3(1, 0, 0), v3(0, 0, 0), 0.5f, 0.5f, v3(0, 0, 0), front};
    bsdf b;
    bsdf_init(&b, m, NULL, m->albedo, &site);
    b.compensate = compensate;
    return b;
}

static vec3 dir_of(double cos_t, double phi) {
    double s = sqrt(fmax(0.0, 1.0 - cos_t * cos_t));
    return v3((float)(s * cos(phi)), (float)(s * sin(phi)), (float)cos_t);
}

static material conductor_f0(float rough, float f0) {
    material m = material_default(MAT_CONDUCTOR);
    m.fresnel = FRESNEL_SCHLICK_F0;
    m.f0 = v3s(f0);
    m.roughness = rough;
    return m;
}

static material conductor_metal(float rough, const char *name, float anisotropy) {
    material m = material_default(MAT_CONDUCTOR);
    material_conductor_preset(name, &m.eta, &m.k);
    m.roughness = rough;
    m.anisotropy = anisotropy;
    return m;
}

// The book's metal with fuzz `fuzz` (also in `roughness`, which it ignores: the chi-square table prints it).
static material book_metal(float fuzz) {
    material m = material_default(MAT_METAL);
    m.albedo = v3(0.9f, 0.7f, 0.3f);
    m.fuzz = m.roughness = fuzz;
    return m;
}

static material glass(float rough, float ior) {
    material m = material_default(MAT_ROUGH_DIELECTRIC);
    m.roughness = rough;
    m.ior = ior;
    return m;
}

static material pbr(float rough, float metallic, float transmission, vec3 base) {
    material m = material_default(MAT_PBR);
    m.roughness = rough;
    m.metallic = metallic;
    m.transmission = transmission;
    m.albedo = base;
    return m;
}

// ---------------------------------------------------------------------------------------------
// White furnace

// The albedo of b at wo by its sample weights (mean of the weight's green channel over n samples) and the standard
// error; checks every weight against f cos / pdf from bsdf_eval and bsdf_pdf.
static double furnace(const bsdf *b, vec3 wo, int n, double *stderr_out, int *mismatches) {
    rng r = rng_for_sample(7, (uint64_t)(wo.z * 1e6f), 3);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; i++) {
        bsdf_sample_record s;
        double w = 0.0;
        if (bsdf_sample(b, wo, &r, &s)) {
            w = s.weight.y;
            if (s.pdf > 0.0f) {
                vec3 f = bsdf_eval(b, wo, s.wi);
                float pdf = bsdf_pdf(b, wo, s.wi);
                double expect = (double)f.y * fabs((double)v3_dot(s.wi, b->n)) / (double)pdf;
                if (!(fabs(expect - w) <= 1e-3 * fmax(1.0, fabs(w))) || !(fabs(pdf - s.pdf) <= 1e-3f * s.pdf))
                    ++*mismatches;
            }
        }
        sum += w;
        sum2 += w * w;
    }
    double mean = sum / n;
    *stderr_out = sqrt(fmax(0.0, sum2 / n - mean * mean) / n);
    return mean;
}

static void test_furnace(void) {
    static const float roughs[] = {0.05f, 0.2f, 0.5f, 1.0f};
    static const double cosines[] = {0.05, 0.2, 0.4, 0.6, 0.8, 1.0};
    enum { N = 20000 };
    struct {
        const char *name;
        material m;
        bool front;
        bool report_only; ///< printed, not checked
    } cases[] = {
        {"conductor f0=1", conductor_f0(0, 1), true, false},
        {"rough_dielectric ior 1.5, entering", glass(0, 1.5f), true, false},
        {"rough_dielectric ior 1.5, leaving", glass(0, 1.5f), false, false},
        {"pbr metallic=1 base=1", pbr(0, 1, 0, v3s(1)), true, false},
        {"pbr transmission=1 base=1", pbr(0, 0, 1, v3s(1)), true, false},
        {"pbr dielectric base=1", pbr(0, 0, 0, v3s(1)), true, false},
    };
    printf("White furnace (albedo / F0 = 1, uniform unit environment): sample-weight mean over %d samples\n", N);
    printf("%-36s %5s |", "material", "rough");
    for (size_t c = 0; c < sizeof cosines / sizeof cosines[0]; c++) printf(" cos=%-4.2f", cosines[c]);
    printf(" | uncompensated min..max\n");
    int mismatches = 0;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++)
        for (size_t j = 0; j < sizeof roughs / sizeof roughs[0]; j++) {
            material m = cases[k].m;
            m.roughness = roughs[j];
            bsdf on = make(&m, cases[k].front, true), off = make(&m, cases[k].front, false);
            printf("%-36s %5.2f |", cases[k].name, (double)roughs[j]);
            double lo = 1e9, hi = -1e9;
            for (size_t c = 0; c < sizeof cosines / sizeof cosines[0]; c++) {
                vec3 wo = dir_of(cosines[c], 0.7);
                double se, se2;
                double e = furnace(&on, wo, N, &se, &mismatches);
                double e0 = furnace(&off, wo, N, &se2, &mismatches);
                printf(" %8.4f", e);
                lo = fmin(lo, e0);
                hi = fmax(hi, e0);
                if (!cases[k].report_only) {
                    CHECK(fabs(e - 1.0) <= 0.01 + 3.0 * se);
                    CHECK(e0 <= 1.0 + 3.0 * se2 + 1e-4);
                }
            }
            printf(" | %.4f..%.4f\n", lo, hi);
        }
    CHECK(mismatches == 0);
    if (mismatches) fprintf(stderr, "%d sample weights differ from f cos / pdf\n", mismatches);
    // IOR 1 is no interface: the ray goes straight on, all of it.
    for (int front = 0; front < 2; front++) {
        material m = glass(0.5f, 1.0f);
        bsdf b = make(&m, front, true);
        vec3 wo = dir_of(0.3, 1.0);
        rng r = rng_for_sample(1, 2, 3);
        bsdf_sample_record s;
        CHECK(bsdf_sample(&b, wo, &r, &s));
        CHECK(s.wi.x == -wo.x && s.wi.y == -wo.y && s.wi.z == -wo.z);
        CHECK(s.weight.x == 1.0f && s.weight.y == 1.0f && s.weight.z == 1.0f);
        CHECK(v3_max_comp(bsdf_eval(&b, wo, v3(0, 0, 1))) == 0.0f);
        material p = pbr(0.5f, 0.0f, 1.0f, v3s(1.0f));
        p.ior = 1.0f;
        b = make(&p, front, true);
        double se;
        int mm = 0;
        CHECK_NEAR(furnace(&b, wo, 4000, &se, &mm), 1.0, 1e-6);
    }
}

// ---------------------------------------------------------------------------------------------
// Chi-square goodness of fit

enum { THETA_BINS = 16, PHI_BINS = 32 };

typedef struct pdf_ctx {
    const bsdf *b;
    vec3 wo;
    double theta; // the outer integral's current theta
} pdf_ctx;

// The pdf per unit (theta, phi): pdf(w) sin(theta).
static double pdf_angles(const pdf_ctx *c, double theta, double phi) {
    double st = sin(theta);
    vec3 wi = v3((float)(st * cos(phi)), (float)(st * sin(phi)), (float)cos(theta));
    return (double)bsdf_pdf(c->b, c->wo, wi) * st;
}

typedef double (*fn1)(pdf_ctx *c, double x);

static double adaptive_simpson(pdf_ctx *c, fn1 f, double a, double b, double fa, double fm, double fb, double whole,
                               double eps, int depth) {
    double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    double flm = f(c, lm), frm = f(c, rm);
    double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    double delta = left + right - whole;
    if (depth <= 0 || fabs(delta) <= 15.0 * eps) return left + right + delta / 15.0;
    return adaptive_simpson(c, f, a, m, fa, flm, fm, left, 0.5 * eps, depth - 1) +
           adaptive_simpson(c, f, m, b, fm, frm, fb, right, 0.5 * eps, depth - 1);
}

// Integral of f over [a, b]: a fixed split into 4 pieces (so that narrow peaks are seen), each adaptive.
static double integrate(pdf_ctx *c, fn1 f, double a, double b, double eps) {
    double sum = 0.0, h = (b - a) / 4.0;
    for (int i = 0; i < 4; i++) {
        double x0 = a + i * h, x1 = x0 + h, fa = f(c, x0), fb = f(c, x1), fm = f(c, 0.5 * (x0 + x1));
        sum += adaptive_simpson(c, f, x0, x1, fa, fm, fb, h / 6.0 * (fa + 4.0 * fm + fb), eps / 4.0, 14);
    }
    return sum;
}

static double phi_lo, phi_hi;

static double inner_phi(pdf_ctx *c, double phi) { return pdf_angles(c, c->theta, phi); }

static double outer_theta(pdf_ctx *c, double theta) {
    c->theta = theta;
    return integrate(c, inner_phi, phi_lo, phi_hi, 1e-6);
}

// The regularised upper incomplete gamma function Q(a, x) (series below a + 1, continued fraction above).
static double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    double gln = lgamma(a);
    if (x < a + 1.0) {
        double ap = a, sum = 1.0 / a, del = sum;
        for (int n = 0; n < 10000; n++) {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if (fabs(del) < fabs(sum) * 1e-15) break;
        }
        return 1.0 - sum * exp(-x + a * log(x) - gln);
    }
    double b = x + 1.0 - a, cc = 1.0 / 1e-300, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; i++) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (fabs(d) < 1e-300) d = 1e-300;
        cc = b + an / cc;
        if (fabs(cc) < 1e-300) cc = 1e-300;
        d = 1.0 / d;
        double del = d * cc;
        h *= del;
        if (fabs(del - 1.0) < 1e-15) break;
    }
    return exp(-x + a * log(x) - gln) * h;
}

typedef struct chi2_case {
    char name[64];
    material m;
    bool front;
    double cos_o;
} chi2_case;

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

// Runs one chi-square test; returns its p-value and prints a row.
static double chi2_test(const chi2_case *tc, int samples) {
    bsdf b = make(&tc->m, tc->front, true);
    vec3 wo = dir_of(tc->cos_o, 0.4);
    static double observed[THETA_BINS * PHI_BINS + 1], expected[THETA_BINS * PHI_BINS + 1];
    memset(observed, 0, sizeof observed);
    rng r = rng_for_sample(11, (uint64_t)(tc->cos_o * 1000), (uint64_t)(tc->m.roughness * 1000));
    int fails = 0;
    for (int i = 0; i < samples; i++) {
        bsdf_sample_record s;
        if (!bsdf_sample(&b, wo, &r, &s)) {
            fails++;
            continue;
        }
        double theta = acos(fmax(-1.0, fmin(1.0, (double)s.wi.z))), phi = atan2((double)s.wi.y, (double)s.wi.x);
        if (phi < 0) phi += 2.0 * PI;
        int ti = (int)(theta / PI * THETA_BINS), pj = (int)(phi / (2.0 * PI) * PHI_BINS);
        ti = ti < THETA_BINS ? ti : THETA_BINS - 1;
        pj = pj < PHI_BINS ? pj : PHI_BINS - 1;
        observed[ti * PHI_BINS + pj]++;
    }
    observed[THETA_BINS * PHI_BINS] = fails;
    pdf_ctx c = {&b, wo, 0.0};
    double mass = 0.0;
    for (int ti = 0; ti < THETA_BINS; ti++)
        for (int pj = 0; pj < PHI_BINS; pj++) {
            phi_lo = 2.0 * PI * pj / PHI_BINS;
            phi_hi = 2.0 * PI * (pj + 1) / PHI_BINS;
            double e = integrate(&c, outer_theta, PI * ti / THETA_BINS, PI * (ti + 1) / THETA_BINS, 1e-6);
            expected[ti * PHI_BINS + pj] = e * samples;
            mass += e;
        }
    expected[THETA_BINS * PHI_BINS] = fmax(0.0, 1.0 - mass) * samples;
    // Pool the bins expected to hold fewer than 5 samples into one.
    double chi2 = 0.0, pool_o = 0.0, pool_e = 0.0;
    int dof = 0;
    for (int i = 0; i <= THETA_BINS * PHI_BINS; i++) {
        if (expected[i] < 5.0) {
            pool_o += observed[i];
            pool_e += expected[i];
            continue;
        }
        chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        dof++;
    }
    if (pool_e >= 5.0) {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        dof++;
    } else if (pool_o > 20.0) {
        chi2 += 1e9; // samples where the pdf says there are none
    }
    dof -= 1;
    double p = dof > 0 ? gamma_q(0.5 * dof, 0.5 * chi2) : 1.0;
    printf("%-40s %5.2f %6.3f %9.4f %9.4f %10.1f %5d %9.2e\n", tc->name, (double)tc->m.roughness, tc->cos_o, mass,
           1.0 - (double)fails / samples, chi2, dof, p);
    // The pdf's mass is the probability that a sample is drawn (not absorbed): within a few standard errors.
    CHECK(fabs(mass - (1.0 - (double)fails / samples)) < 5.0 * sqrt(0.25 / samples) + 2e-3);
    return p;
}

static void test_chi2(void) {
    static const float roughs[] = {0.1f, 0.3f, 0.6f, 1.0f};
    static const double cosines[] = {0.25, 0.6, 0.95};
    chi2_case cases[128];
    int n = 0;
    for (size_t j = 0; j < 4; j++) {
        cases[n++] = (chi2_case){"conductor Au", conductor_metal(roughs[j], "Au", 0.0f), true, 0};
        cases[n++] = (chi2_case){"rough_dielectric ior 1.5 entering", glass(roughs[j], 1.5f), true, 0};
        cases[n++] = (chi2_case){"rough_dielectric ior 1.5 leaving", glass(roughs[j], 1.5f), false, 0};
        cases[n++] = (chi2_case){"rough_dielectric ior 1.33 entering", glass(roughs[j], 1.33f), true, 0};
        cases[n++] = (chi2_case){"pbr dielectric base 0.8", pbr(roughs[j], 0.0f, 0.0f, v3s(0.8f)), true, 0};
    }
    // The book's fuzzed metal at fuzz 1 (cos/pi about the mirror direction, part of it below the surface at oblique
    // incidence); narrower cones have an edge of infinite density that the integration above cannot follow
    // (test_metal_density checks them against their exact distribution).
    cases[n++] = (chi2_case){"metal (the book's), fuzz", book_metal(1.0f), true, 0};
    cases[n++] = (chi2_case){"conductor Cu anisotropy 0.8", conductor_metal(0.4f, "Cu", 0.8f), true, 0};
    cases[n++] = (chi2_case){"pbr metallic 1 base (1,.7,.3)", pbr(0.4f, 1.0f, 0.0f, v3(1, .7f, .3f)), true, 0};
    cases[n++] = (chi2_case){"pbr metallic .3 transm .5", pbr(0.5f, 0.3f, 0.5f, v3s(0.9f)), true, 0};
    cases[n++] = (chi2_case){"pbr transmission 1 ior 1.5", pbr(0.3f, 0.0f, 1.0f, v3s(1.0f)), true, 0};
    cases[n++] = (chi2_case){"pbr transmission 1 leaving", pbr(0.3f, 0.0f, 1.0f, v3s(1.0f)), false, 0};
    int base = n;
    // Each case at three incidences.
    for (int i = 0; i < base; i++)
        for (int c = 1; c < 3; c++) {
            cases[n] = cases[i];
            cases[n++].cos_o = cosines[c];
        }
    for (int i = 0; i < base; i++) cases[i].cos_o = cosines[0];
    double alpha = 1.0 - pow(1.0 - 0.01, 1.0 / n); // Sidak: significance 0.01 over all n tests
    printf("\nChi-square goodness of fit of bsdf_sample against bsdf_pdf (%d x %d (theta, phi) bins, 50000 samples;\n"
           "reject below p = %.2e, 0.01 after Sidak's correction for %d tests)\n",
           THETA_BINS, PHI_BINS, alpha, n);
    printf("%-40s %5s %6s %9s %9s %10s %5s %9s\n", "lobe", "rough", "cos_o", "int pdf", "drawn", "chi2", "dof", "p");
    double pv[128];
    for (int i = 0; i < n; i++) {
        pv[i] = chi2_test(&cases[i], 50000);
        CHECK(pv[i] >= alpha);
    }
    qsort(pv, (size_t)n, sizeof pv[0], cmp_double);
    printf("smallest p-value %.3g, median %.3g\n", pv[0], pv[n / 2]);
}

// ---------------------------------------------------------------------------------------------
// The book's fuzzed metal: its density against its sampling

// At normal incidence the cosine c between a sampled direction and the mirror direction has the distribution
// F(c) = c sqrt(c^2 - a^2) / fuzz on [a, 1], a^2 = 1 - fuzz^2 (the integral of 2 pi mat_metal_pdf over the cap;
// d/dc of c sqrt(c^2 - a^2) is (2c^2 - a^2) / sqrt(c^2 - a^2)). Checks the density against F's derivative and the
// samples against F (chi-square, 20 bins of equal probability), and that every sample's weight is f cos / pdf.
static void test_metal_density(void) {
    static const float fuzzes[] = {0.02f, 0.1f, 0.3f, 0.6f, 1.0f};
    enum { BINS = 20, SAMPLES = 50000 };
    double alpha = 1.0 - pow(1.0 - 0.01, 1.0 / 5.0);
    printf("\nThe book's fuzzed metal at normal incidence: the cosine to the mirror direction against its exact\n"
           "distribution (%d bins of equal probability, %d samples; reject below p = %.2e)\n", BINS, SAMPLES, alpha);
    for (size_t k = 0; k < sizeof fuzzes / sizeof fuzzes[0]; k++) {
        double f = fuzzes[k], a2 = 1.0 - f * f;
        material m = book_metal(fuzzes[k]);
        bsdf b = make(&m, true, true);
        CHECK(bsdf_has_nee(&b) && !(b.flags & BSDF_DELTA));
        vec3 wo = v3(0, 0, 1);
        // The density: 2 pi pdf = F'(c), at cosines across the cone.
        for (int i = 1; i < 10; i++) {
            double c = sqrt(a2) + (1.0 - sqrt(a2)) * i / 10.0;
            double want = (2.0 * c * c - a2) / (f * sqrt(c * c - a2)) / (2.0 * PI);
            CHECK_NEAR(bsdf_pdf(&b, wo, dir_of(c, 0.3 * i)), want, 2e-3 * want);
        }
        CHECK(bsdf_pdf(&b, wo, dir_of(sqrt(a2) * 0.999, 1.0)) == 0.0f); // outside the cone
        // The samples: the bin of each cosine by F, and every sample's weight.
        int count[BINS] = {0}, fails = 0, edge = 0;
        rng r = rng_for_sample(5, k, 0);
        for (int i = 0; i < SAMPLES; i++) {
            bsdf_sample_record sr;
            if (!bsdf_sample(&b, wo, &r, &sr)) {
                fails++;
                continue;
            }
            double c = fmin(1.0, (double)sr.wi.z), F = c * sqrt(fmax(0.0, c * c - a2)) / f;
            int bin = (int)(F * BINS);
            count[bin < BINS ? bin : BINS - 1]++;
            CHECK((sr.flags & BSDF_GLOSSY) && sr.pdf > 0.0f);
            if (sr.pdf == FLT_MAX) { // drawn at the cone's edge and put just outside it by rounding
                edge++;
                continue;
            }
            vec3 fc = v3_scale(bsdf_eval(&b, wo, sr.wi), sr.wi.z / sr.pdf);
            CHECK_NEAR(fc.x, sr.weight.x, 1e-3 * sr.weight.x);
        }
        double chi2 = 0.0, e = (double)(SAMPLES - fails) / BINS;
        for (int i = 0; i < BINS; i++) chi2 += (count[i] - e) * (count[i] - e) / e;
        double p = gamma_q(0.5 * (BINS - 1), 0.5 * chi2);
        printf("  fuzz %.2f: chi2 %6.1f (%d dof), p %.3g, absorbed %d, outside the edge by rounding %d\n", f, chi2,
               BINS - 1, p, fails, edge);
        CHECK(p >= alpha);
        CHECK(edge <= SAMPLES / 1000);
        CHECK(fails <= SAMPLES / 1000); // none but rounding's at fuzz < 1 (the cone lies above the surface)
        // Oblique incidence: the density is the cone's about the mirror direction, none below the surface.
        vec3 wo2 = dir_of(0.3, 0.8), mirror = v3_reflect(v3_neg(wo2), v3(0, 0, 1));
        vec3 in_cone = v3_unit(v3_fma(mirror, v3(0, 0, 1), 0.5f * fuzzes[k]));
        CHECK(bsdf_pdf(&b, wo2, in_cone) == mat_metal_pdf(mirror, fuzzes[k], in_cone));
        CHECK(bsdf_pdf(&b, wo2, v3(in_cone.x, in_cone.y, -in_cone.z)) == 0.0f);
    }
    material mirror = book_metal(0.0f);
    bsdf b = make(&mirror, true, true);
    CHECK(!bsdf_has_nee(&b) && (b.flags & BSDF_DELTA)); // a perfect mirror: no density
}

// ---------------------------------------------------------------------------------------------
// Reciprocity, and the book's materials through the interface

static void test_reciprocity(void) {
    material ms[] = {conductor_metal(0.3f, "Au", 0.0f), conductor_metal(0.7f, "Fe", 0.5f), conductor_f0(0.2f, 0.9f),
                     pbr(0.4f, 0.0f, 0.0f, v3(0.8f, 0.5f, 0.2f)), pbr(0.8f, 0.6f, 0.0f, v3(0.3f, 0.9f, 0.5f))};
    rng r = rng_for_sample(5, 6, 7);
    int bad = 0, nonzero = 0;
    for (size_t k = 0; k < sizeof ms / sizeof ms[0]; k++) {
        bsdf b = make(&ms[k], true, true);
        for (int i = 0; i < 2000; i++) {
            vec3 a = dir_of(0.02 + 0.98 * rng_float(&r), 6.2831853 * rng_float(&r));
            vec3 c = dir_of(0.02 + 0.98 * rng_float(&r), 6.2831853 * rng_float(&r));
            vec3 f1 = bsdf_eval(&b, a, c), f2 = bsdf_eval(&b, c, a);
            nonzero += v3_max_comp(f1) > 0.0f;
            vec3 d = v3_sub(f1, f2);
            if (fmaxf(fabsf(d.x), fmaxf(fabsf(d.y), fabsf(d.z))) > 1e-4f * fmaxf(1.0f, v3_max_comp(f1))) bad++;
        }
    }
    CHECK(bad == 0);
    CHECK(nonzero > 9000);
}

// The book's materials sample exactly as mat_scatter does (the same random numbers, the same directions).
static void test_classic_materials(void) {
    material ms[] = {material_default(MAT_LAMBERTIAN), material_default(MAT_METAL), material_default(MAT_DIELECTRIC),
                     material_default(MAT_PHONG)};
    ms[1].fuzz = 0.3f;
    ms[3].reflective = 0.4f;
    for (size_t k = 0; k < 4; k++)
        for (int front = 0; front < 2; front++) {
            bsdf b = make(&ms[k], front, true);
            vec3 wo = dir_of(0.6, 0.2);
            rng r1 = rng_for_sample(3, k, 9), r2 = r1;
            for (int i = 0; i < 100; i++) {
                bsdf_sample_record s;
                scatter_event ev;
                bool a = bsdf_sample(&b, wo, &r1, &s), c = mat_scatter(&ms[k], ms[k].albedo, v3_neg(wo), v3(0, 0, 1),
                                                                     front, &r2, &ev);
                CHECK(a == c);
                if (a && c) CHECK(s.wi.x == ev.dir.x && s.wi.y == ev.dir.y && s.wi.z == ev.dir.z);
            }
            CHECK(r1.state == r2.state);
        }
    material l = material_default(MAT_LAMBERTIAN);
    bsdf b = make(&l, true, true);
    CHECK_NEAR(bsdf_eval(&b, v3(0, 0, 1), dir_of(0.5, 1.0)).x, 0.5 / PI, 1e-7);
    CHECK_NEAR(bsdf_pdf(&b, v3(0, 0, 1), dir_of(0.5, 1.0)), 0.5 / PI, 1e-7);
    CHECK(bsdf_has_nee(&b));
    material d = material_default(MAT_DIELECTRIC);
    b = make(&d, true, true);
    CHECK(!bsdf_has_nee(&b) && (b.flags & BSDF_DELTA));
}

// The Fresnel formulas at points with known values.
static void test_fresnel(void) {
    CHECK_NEAR(mf_fresnel_dielectric(1.0f, 1.5f), 0.04, 1e-6);
    CHECK_NEAR(mf_fresnel_dielectric(1.0f, 1.0f / 1.5f), 0.04, 1e-6);
    CHECK(mf_fresnel_dielectric(0.3f, 1.0f / 1.5f) == 1.0f); // beyond the critical angle
    CHECK_NEAR(mf_fresnel_dielectric(0.5f, 1.0f), 0.0, 1e-7);
    // A conductor of k = 0 is a dielectric; normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
    CHECK_NEAR(mf_fresnel_conductor1(0.7f, 1.5f, 0.0f), mf_fresnel_dielectric(0.7f, 1.5f), 1e-5);
    CHECK_NEAR(mf_fresnel_conductor1(1.0f, 0.2f, 3.0f), (0.64 + 9.0) / (1.44 + 9.0), 1e-5);
    CHECK_NEAR(mf_fresnel_conductor1(0.0f, 0.2f, 3.0f), 1.0, 1e-5);
    // Visible normals integrate to 1 (a coarse midpoint check of mf_visible_d over the hemisphere).
    vec3 wo = dir_of(0.5, 0.3);
    double sum = 0.0;
    int n = 400;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double ct = (i + 0.5) / n, phi = 2 * PI * (j + 0.5) / n;
            sum += mf_visible_d(wo, dir_of(ct, phi), 0.5f, 0.3f) * (1.0 / n) * (2 * PI / n);
        }
    CHECK_NEAR(sum, 1.0, 2e-3);
}

// Both strategies of next-event estimation's MIS estimate the light a rectangle above the surface reflects towards
// wo the same: BSDF samples that hit it (weight f cos / pdf), and uniform points on it (f cos cos_l / (d^2 pdf_A)).
static void test_strategies_agree(void) {
    material ms[] = {conductor_metal(0.5f, "Au", 0.0f), conductor_f0(0.9f, 1.0f), pbr(0.6f, 0.0f, 0.0f, v3s(0.8f)),
                     glass(0.5f, 1.5f)};
    static const double cosines[] = {0.7, 0.2, 0.05};
    for (size_t k = 0; k < sizeof ms / sizeof ms[0] * 3; k++) {
        bsdf b = make(&ms[k / 3], true, true);
        vec3 wo = dir_of(cosines[k % 3], 0.3);
        // The rectangle [-1, 2] x [-0.5, 1.5] at height 1 (z), facing down.
        vec3 q0 = v3(-1, -0.5f, 1), eu = v3(3, 0, 0), ev = v3(0, 2, 0);
        float area = 6.0f;
        rng r = rng_for_sample(9, k, 1);
        double by_bsdf = 0.0, by_light = 0.0;
        int n = 200000;
        for (int i = 0; i < n; i++) {
            bsdf_sample_record s;
            if (bsdf_sample(&b, wo, &r, &s) && s.wi.z > 0.0f) {
                float t = 1.0f / s.wi.z;
                float x = s.wi.x * t, y = s.wi.y * t;
                if (x >= -1 && x <= 2 && y >= -0.5f && y <= 1.5f) by_bsdf += s.weight.y;
            }
            vec3 p = v3_add(q0, v3_add(v3_scale(eu, rng_float(&r)), v3_scale(ev, rng_float(&r))));
            float d2 = v3_len2(p);
            vec3 wi = v3_scale(p, 1.0f / sqrtf(d2));
            by_light += (double)bsdf_eval(&b, wo, wi).y * wi.z * wi.z / d2 * area;
        }
        by_bsdf /= n;
        by_light /= n;
        printf("light from a rectangle, case %zu: BSDF sampling %.5f, area sampling %.5f\n", k, by_bsdf, by_light);
        CHECK_NEAR(by_bsdf, by_light, 0.02 * by_light + 3e-4);
    }
}

// glTF's baseColorFactor multiplies a base colour texture (the importer sets base_factor); without a texture the
// base colour is the constant itself.
static void test_base_factor(void) {
    texture tex = texture_solid(v3(0.8f, 0.6f, 0.4f));
    material m = pbr(0.5f, 0.0f, 0.0f, v3s(0.3f));
    m.albedo_texture = 0;
    m.base_factor = v3(0.5f, 1.0f, 0.25f);
    bsdf_site site = {v3(0, 0, 1), v3(1, 0, 0), v3(0, 0, 0), 0.5f, 0.5f, v3(0, 0, 0), true};
    bsdf b;
    bsdf_init(&b, &m, &tex, v3(0.8f, 0.6f, 0.4f), &site);
    CHECK(b.base.x == 0.4f && b.base.y == 0.6f && b.base.z == 0.1f);
    m.albedo_texture = -1;
    bsdf_init(&b, &m, &tex, m.albedo, &site);
    CHECK(b.base.x == 0.3f && b.base.y == 0.3f && b.base.z == 0.3f);
}

int main(void) {
    test_base_factor();
    test_strategies_agree();
    test_fresnel();
    test_classic_materials();
    test_reciprocity();
    test_furnace();
    test_chi2();
    test_metal_density();
    return check_summary();
}
