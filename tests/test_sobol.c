// test_sobol.c — the Sobol' generator matrices (Joe & Kuo's direction numbers) give the sequence's published first
// points; the fast forms of dimensions 0 and 1 are those matrices; every dimension is a (0,1)-sequence and
// dimensions 0 and 1 a (0,2)-sequence; the sampler's scrambling and shuffling keep the (0,m,2)-net of every
// decision's pair at 2^m samples; its 2-D L2-star discrepancy lies below the independent sampler's; and the
// sampler's state (rng_float, rng_start_bounce, rng_decision) draws the dimensions it says, while PCG32 is
// untouched by them.
#include "check.h"
#include "core/rng.h"
#include "core/sobol.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// The first eight points of the unscrambled 4-D sequence in Gray-code order (point n is the XOR of the columns
// of the bits of n ^ (n >> 1)), as Joe & Kuo's generator and every library built on their numbers print them.
static const double published[8][4] = {
    {0, 0, 0, 0},
    {0.5, 0.5, 0.5, 0.5},
    {0.75, 0.25, 0.25, 0.25},
    {0.25, 0.75, 0.75, 0.75},
    {0.375, 0.375, 0.625, 0.875},
    {0.875, 0.875, 0.125, 0.375},
    {0.625, 0.125, 0.875, 0.625},
    {0.125, 0.625, 0.375, 0.125},
};

static void test_published_points(void) {
    for (uint32_t n = 0; n < 8; n++)
        for (int d = 0; d < 4; d++) CHECK(sobol_point(n ^ (n >> 1), d) == (uint32_t)(published[n][d] * 4294967296.0));
}

// Dimension 0 is the bit reversal of the index, dimension 1 the reversed superset sum (sobol_dim1_reversed).
static void test_fast_dimensions(void) {
    uint64_t lcg = 1;
    int wrong = 0;
    for (int i = 0; i < 100000; i++) {
        uint32_t index = i < 50000 ? (uint32_t)i : (uint32_t)((lcg = lcg * 6364136223846793005ULL + 1) >> 32);
        wrong += sobol_point(index, 0) != sobol_reverse_bits(index);
        wrong += sobol_point(index, 1) != sobol_reverse_bits(sobol_dim1_reversed(index));
    }
    CHECK(wrong == 0);
}

// Column k of every matrix has its lowest bit at fraction digit k + 1 (m_(k+1) odd): the matrices are
// nonsingular triangular, so each dimension's first 2^m points fall one in each interval of
// width 2^-m.
static void test_one_dimensional_stratification(void) {
    for (int d = 0; d < SOBOL_DIMENSIONS; d++) {
        uint32_t c[32];
        sobol_matrix(d, c);
        bool triangular = true;
        for (int k = 0; k < 32; k++)
            triangular = triangular && ((c[k] >> (31 - k)) & 1u) && (c[k] & ((1u << (31 - k)) - 1u)) == 0;
        CHECK(triangular);
        for (int m = 1; m <= 12; m++) {
            unsigned char seen[4096] = {0};
            bool once = true;
            for (uint32_t i = 0; i < (1u << m); i++) once = once && !seen[sobol_point(i, d) >> (32 - m)]++;
            if (!once) fprintf(stderr, "dimension %d is not stratified at 2^%d points\n", d, m);
            CHECK(once);
        }
    }
}

// Whether the 2^m points (x[i], y[i]) form a (0,m,2)-net: one point in each elementary interval of every shape
// 2^-a x 2^-(m-a).
static bool is_net(const uint32_t *x, const uint32_t *y, int m) {
    static unsigned char seen[1 << 16];
    for (int a = 0; a <= m; a++) {
        memset(seen, 0, (size_t)1 << m);
        for (uint32_t i = 0; i < (1u << m); i++) {
            uint32_t cx = a ? x[i] >> (32 - a) : 0, cy = m - a ? y[i] >> (32 - (m - a)) : 0;
            uint32_t cell = (cx << (m - a)) | cy;
            if (seen[cell]++) return false;
        }
    }
    return true;
}

enum { NET_MAX = 1 << 12 };
static uint32_t xs[NET_MAX], ys[NET_MAX];

// The unscrambled dimensions 0 and 1 form a (0,m,2)-net in every aligned block of 2^m indices.
static void test_unscrambled_net(void) {
    for (int m = 1; m <= 12; m++)
        for (uint32_t block = 0; block < 3; block++) {
            uint32_t base = block * 7919u << m;
            for (uint32_t i = 0; i < (1u << m); i++) xs[i] = sobol_point(base + i, 0), ys[i] = sobol_point(base + i, 1);
            CHECK(is_net(xs, ys, m));
        }
}

// The sampler's dimension of depth field `depth`, offset `offset`.
static uint32_t dim_of(int depth, int offset) { return ((uint32_t)depth << 15) | (uint32_t)offset; }

// After the per-pixel shuffle and the Owen scrambling, the first 2^m samples of a pixel still form a (0,m,2)-net
// in each decision's pair of dimensions: the camera's film point, a bounce's BSDF direction and light point.
static void test_sampler_net(void) {
    static const int pairs[][2] = {{0, RNG_DIM_FILM}, {0, RNG_DIM_LENS}, {1, RNG_DIM_BSDF}, {4, RNG_DIM_LIGHT + 1},
                                   {51, RNG_DIM_ENVIRONMENT}};
    int bad = 0, checked = 0;
    for (uint64_t pixel = 0; pixel < 20; pixel++) {
        uint64_t key = rng_pixel_key(7, pixel);
        for (size_t p = 0; p < sizeof pairs / sizeof pairs[0]; p++)
            for (int m = 0; m <= 12; m += 2) {
                uint32_t dx = dim_of(pairs[p][0], pairs[p][1]);
                for (uint32_t i = 0; i < (1u << m); i++)
                    xs[i] = sobol_sampler_u32(key, i, dx), ys[i] = sobol_sampler_u32(key, i, dx + 1);
                bad += !is_net(xs, ys, m);
                checked++;
            }
    }
    if (bad) fprintf(stderr, "%d of %d scrambled pairs are not (0,m,2)-nets\n", bad, checked);
    CHECK(bad == 0);
    // Two pixels' film points differ (per-pixel decorrelation), and so do two decisions' of one pixel.
    uint64_t k0 = rng_pixel_key(7, 0), k1 = rng_pixel_key(7, 1);
    int same_pixels = 0, same_dims = 0;
    for (uint32_t i = 0; i < 64; i++) {
        same_pixels += sobol_sampler_u32(k0, i, 0) == sobol_sampler_u32(k1, i, 0);
        same_dims += sobol_sampler_u32(k0, i, dim_of(1, 0)) == sobol_sampler_u32(k0, i, dim_of(2, 0));
    }
    CHECK(same_pixels < 4 && same_dims < 4);
}

// Warnock's formula for the L2-star discrepancy of n points in the unit square.
static double l2_star(const double *x, const double *y, int n) {
    double a = 0.0, b = 0.0;
    for (int i = 0; i < n; i++) {
        a += (1.0 - x[i] * x[i]) * (1.0 - y[i] * y[i]);
        for (int j = 0; j < n; j++) b += (1.0 - fmax(x[i], x[j])) * (1.0 - fmax(y[i], y[j]));
    }
    return sqrt(1.0 / 9.0 - a / (2.0 * n) + b / ((double)n * n));
}

// The film points of the first 2^k samples of 32 pixels: the Sobol' sampler's 2-D discrepancy lies well below
// PCG32's (independent samples: about sqrt(1/n)), on average over the pixels, for the camera and a bounce.
static void test_discrepancy(void) {
    static double px[1024], py[1024], qx[1024], qy[1024];
    uint64_t stream = rng_seed_stream(3);
    for (int k = 4; k <= 10; k += 2) {
        int n = 1 << k;
        double sobol_sum = 0.0, bounce_sum = 0.0, random_sum = 0.0;
        for (uint64_t pixel = 0; pixel < 32; pixel++) {
            uint64_t key = rng_pixel_key(3, pixel);
            for (int i = 0; i < n; i++) {
                rng s = rng_sobol(key, (uint64_t)i);
                px[i] = rng_float(&s);
                py[i] = rng_float(&s);
                rng_start_bounce(&s, 2);
                rng_decision(&s, RNG_DIM_LIGHT + 1);
                qx[i] = rng_float(&s);
                qy[i] = rng_float(&s);
            }
            sobol_sum += l2_star(px, py, n);
            bounce_sum += l2_star(qx, qy, n);
            for (int i = 0; i < n; i++) {
                rng r = rng_for_key(stream, key, (uint64_t)i);
                px[i] = rng_float(&r);
                py[i] = rng_float(&r);
            }
            random_sum += l2_star(px, py, n);
        }
        printf("L2-star discrepancy at %4d samples (mean of 32 pixels): sobol film %.5f, sobol bounce 2 light "
               "%.5f, independent %.5f\n", n, sobol_sum / 32, bounce_sum / 32, random_sum / 32);
        CHECK(sobol_sum < 0.5 * random_sum && bounce_sum < 0.5 * random_sum);
    }
}

// rng_float draws the sampler's dimensions in turn; rng_start_bounce and rng_decision move to a bounce's and a
// decision's; PCG32 draws what it always drew, whatever they are told.
static void test_rng_state(void) {
    uint64_t key = rng_pixel_key(11, 12345);
    rng s = rng_sobol(key, 9);
    CHECK(rng_is_sobol(&s));
    float a = rng_float(&s), b = rng_float(&s);
    CHECK(a == sobol_sampler_float(key, 9, 0) && b == sobol_sampler_float(key, 9, 1));
    rng_decision(&s, RNG_DIM_TIME);
    CHECK(rng_float(&s) == sobol_sampler_float(key, 9, RNG_DIM_TIME));
    rng_start_bounce(&s, 3);
    CHECK(rng_float(&s) == sobol_sampler_float(key, 9, dim_of(4, 0)));
    rng_decision(&s, RNG_DIM_MEDIUM);
    CHECK(rng_float(&s) == sobol_sampler_float(key, 9, dim_of(4, RNG_DIM_MEDIUM)));
    CHECK(rng_float(&s) == sobol_sampler_float(key, 9, dim_of(4, RNG_DIM_MEDIUM + 1)));
    rng_start_bounce(&s, 0);
    CHECK(rng_float(&s) == sobol_sampler_float(key, 9, dim_of(1, 0)));
    CHECK((uint32_t)(s.inc >> 32) == sobol_reverse_bits(9u) && s.state == key); // the sample and the pixel stay
    // Values lie in [0, 1).
    bool in_range = true;
    for (uint32_t i = 0; i < 100000; i++) {
        float u = sobol_sampler_float(key, i, i % 7u);
        in_range = in_range && u >= 0.0f && u < 1.0f;
    }
    CHECK(in_range);
    // PCG32 with the sampler's calls in between draws exactly the plain sequence.
    rng p = rng_for_sample(11, 12345, 9), q = p;
    CHECK(!rng_is_sobol(&p));
    bool same = true;
    for (int i = 0; i < 100; i++) {
        if (i % 3 == 0) rng_start_bounce(&p, i);
        if (i % 5 == 0) rng_decision(&p, RNG_DIM_LIGHT);
        same = same && rng_float(&p) == (float)(rng_u32(&q) >> 8) * 0x1.0p-24f;
    }
    CHECK(same && p.state == q.state && p.inc == q.inc);
}

// rng_float2 draws one pair: PCG32's next two numbers; the Sobol' sampler's pair at an even offset, and the next
// pair (one offset skipped) at an odd one, the offset past it either way.
static void test_float2(void) {
    rng p = rng_for_sample(5, 77, 3), q = p;
    float a, b;
    rng_float2(&p, &a, &b);
    CHECK(a == rng_float(&q) && b == rng_float(&q) && p.state == q.state);
    uint64_t key = rng_pixel_key(5, 77);
    for (uint32_t sample = 0; sample < 64; sample++) {
        rng s = rng_sobol(key, sample);
        rng_start_bounce(&s, 2);
        rng_decision(&s, RNG_DIM_BSDF);
        rng_float2(&s, &a, &b);
        CHECK(a == sobol_sampler_float(key, sample, dim_of(3, 0)) && b == sobol_sampler_float(key, sample, dim_of(3, 1)));
        rng_decision(&s, RNG_DIM_LIGHT); // odd: the pair after it
        rng_float2(&s, &a, &b);
        CHECK(a == sobol_sampler_float(key, sample, dim_of(3, RNG_DIM_LIGHT + 1)) &&
              b == sobol_sampler_float(key, sample, dim_of(3, RNG_DIM_LIGHT + 2)));
        CHECK(rng_sobol_dimension(&s) == dim_of(3, RNG_DIM_LIGHT + 3));
    }
}

// Values prepared ahead (rng_prepare) are the values drawn without it, single or in pairs, at even and odd offsets;
// pairs not prepared, another bounce's and the camera's are computed as before; PCG32 is untouched.
static void test_prepare(void) {
    uint64_t key = rng_pixel_key(7, 4242);
    const unsigned all = RNG_AHEAD_BSDF | RNG_AHEAD_LIGHT | RNG_AHEAD_ENVIRONMENT | RNG_AHEAD_MEDIUM;
    const int offsets[] = {RNG_DIM_BSDF, RNG_DIM_BSDF + 1, RNG_DIM_LIGHT, RNG_DIM_LIGHT + 1, RNG_DIM_LIGHT + 2,
                           RNG_DIM_ENVIRONMENT, RNG_DIM_IMPORTANCE, RNG_DIM_MEDIUM, RNG_DIM_MEDIUM + 1,
                           RNG_DIM_MEDIUM + 2};
    int wrong = 0;
    for (uint32_t sample = 0; sample < 32; sample++)
        for (unsigned pairs = 0; pairs <= all; pairs++) {
            if (pairs & ~all) continue;
            for (size_t o = 0; o < sizeof offsets / sizeof offsets[0]; o++) {
                rng s = rng_sobol(key, sample), plain = s;
                rng_prepare(&s, 2, pairs);
                rng_start_bounce(&s, 2);
                rng_start_bounce(&plain, 2);
                rng_decision(&s, offsets[o]);
                rng_decision(&plain, offsets[o]);
                float a, b, c, d;
                a = rng_float(&s), c = rng_float(&plain);
                rng_float2(&s, &a, &b);
                rng_float2(&plain, &c, &d);
                wrong += a != c || b != d || rng_float(&s) != rng_float(&plain) || s.inc != plain.inc;
                wrong += rng_float(&s) != sobol_sampler_float(key, sample, rng_sobol_dimension(&plain));
                rng_start_bounce(&s, 1); // another bounce: nothing prepared for it
                rng_float2(&s, &a, &b);
                wrong += a != sobol_sampler_float(key, sample, dim_of(2, 0)) ||
                         b != sobol_sampler_float(key, sample, dim_of(2, 1));
            }
        }
    CHECK(wrong == 0);
    rng p = rng_for_sample(7, 4242, 5), q = p;
    rng_prepare(&p, 0, all);
    CHECK(p.ahead.pairs == 0 && rng_float(&p) == rng_float(&q) && p.state == q.state);
}

int main(void) {
    test_published_points();
    test_fast_dimensions();
    test_one_dimensional_stratification();
    test_unscrambled_net();
    test_sampler_net();
    test_discrepancy();
    test_rng_state();
    test_float2();
    test_prepare();
    return check_summary();
}
