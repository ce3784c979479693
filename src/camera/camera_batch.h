// camera_batch.h — camera rays sixteen samples at a time, for the path tracer's tile loop: every lane computes
// exactly what rng_for_stream and camera_sample_ray compute for one sample (the same operations in the same
// order, so the same bits), in loops over the lanes that the compiler turns into vector instructions.
#ifndef GLINT_CAMERA_BATCH_H
#define GLINT_CAMERA_BATCH_H

#include "camera/camera.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/sobol.h"

#include <stdint.h>
#include <string.h>

enum { CAMERA_BATCH = 16 };

/// One batch: per lane the pixel, its rng_pixel_key and the sample index (inputs), then the sample's generator
/// after the camera's draws and its primary ray (outputs). Unused lanes must hold some valid sample.
typedef struct camera_batch {
    int x[CAMERA_BATCH], y[CAMERA_BATCH];
    uint64_t key[CAMERA_BATCH], sample[CAMERA_BATCH];
    rng r[CAMERA_BATCH];
    vec3 o[CAMERA_BATCH], d[CAMERA_BATCH];
    float time[CAMERA_BATCH];
} camera_batch;

// rng_u32 in every lane (state st, shared stream inc).
static inline void batch_u32(uint64_t st[CAMERA_BATCH], uint64_t inc, uint32_t out[CAMERA_BATCH]) {
    for (int i = 0; i < CAMERA_BATCH; i++) {
        uint64_t old = st[i];
        st[i] = old * 6364136223846793005ULL + inc;
        uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = (uint32_t)(old >> 59u);
        out[i] = (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
    }
}

// rng_float in every lane.
static inline void batch_float(uint64_t st[CAMERA_BATCH], uint64_t inc, float out[CAMERA_BATCH]) {
    uint32_t u[CAMERA_BATCH];
    batch_u32(st, inc, u);
    for (int i = 0; i < CAMERA_BATCH; i++) out[i] = (float)(u[i] >> 8) * 0x1.0p-24f;
}

// sincos_turn in every lane. floorf(x + 0.5f) is the truncation of that non-negative number.
static inline void batch_sincos_turn(const float u[CAMERA_BATCH], float c[CAMERA_BATCH], float s[CAMERA_BATCH]) {
    float cs[CAMERA_BATCH], sn[CAMERA_BATCH];
    uint32_t k[CAMERA_BATCH], bc[CAMERA_BATCH], bs[CAMERA_BATCH], rc[CAMERA_BATCH], rs[CAMERA_BATCH];
    for (int i = 0; i < CAMERA_BATCH; i++) {
        float x = 4.0f * u[i];
        int32_t qi = (int32_t)(x + 0.5f);
        float q = (float)qi;
        float t = (x - q) * 1.57079632679490f, z = t * t;
        sn[i] = sampling_mad(sampling_mad(sampling_mad(-1.9515295891e-4f, z, 8.3321608736e-3f), z, -1.6666654611e-1f),
                             z * t, t);
        cs[i] = sampling_mad(
            sampling_mad(sampling_mad(sampling_mad(2.443315711809948e-5f, z, -1.388731625493765e-3f), z,
                                      4.166664568298827e-2f),
                         z, -0.5f),
            z, 1.0f);
        k[i] = (uint32_t)qi;
    }
    memcpy(bc, cs, sizeof bc);
    memcpy(bs, sn, sizeof bs);
    for (int i = 0; i < CAMERA_BATCH; i++) {
        uint32_t swap = 0u - (k[i] & 1u);
        rc[i] = ((bs[i] & swap) | (bc[i] & ~swap)) ^ (((k[i] + 1u) & 2u) << 30);
        rs[i] = ((bc[i] & swap) | (bs[i] & ~swap)) ^ ((k[i] & 2u) << 30);
    }
    memcpy(c, rc, sizeof rc);
    memcpy(s, rs, sizeof rs);
}

/// The random numbers of a batch's camera rays: the film point (jx, jy), the lens point (u1, u2) when `lens`, the
/// time (ut) when `shutter`; and each lane's generator after them (b->r).
typedef struct camera_batch_draws {
    float jx[CAMERA_BATCH], jy[CAMERA_BATCH], u1[CAMERA_BATCH], u2[CAMERA_BATCH], ut[CAMERA_BATCH];
} camera_batch_draws;

// The Sobol' sampler's camera dimensions in every lane (RNG_DIM_FILM, RNG_DIM_LENS, RNG_DIM_TIME, as
// camera_sample_ray draws them) and the lanes' samplers at the offset after them. Out of line (and unused where no
// tile loop includes this header's caller): the PCG32 path keeps the tile loops' code as it was.
static __attribute__((noinline, unused)) void camera_batch_sobol(camera_batch *b, bool lens, bool shutter,
                                                                 camera_batch_draws *u) {
    for (int i = 0; i < CAMERA_BATCH; i++) {
        uint64_t key = b->key[i];
        uint32_t reversed = sobol_reverse_bits((uint32_t)b->sample[i]);
        sobol_pair_floats(key, reversed, RNG_DIM_FILM / 2, &u->jx[i], &u->jy[i]);
        int next = RNG_DIM_FILM + 2;
        if (lens) {
            sobol_pair_floats(key, reversed, RNG_DIM_LENS / 2, &u->u1[i], &u->u2[i]);
            next = RNG_DIM_LENS + 2;
        }
        if (shutter) {
            u->ut[i] = sobol_float(sobol_sampler_u32_reversed(key, reversed, RNG_DIM_TIME));
            next = RNG_DIM_TIME + 1;
        }
        b->r[i] = rng_sobol(key, b->sample[i]);
        rng_decision(&b->r[i], next);
    }
}

/// Fills b->r, b->o, b->d and b->time from the inputs: lane i is rng_for_stream(stream, key[i], sample[i])
/// followed by camera_sample_ray(c, x[i], y[i], &r): PCG32's draws, or the Sobol' sampler's camera dimensions.
// Always inlined into the tile loops: a call passes the whole batch through memory (gcc stopped inlining it once
// the path tracer grew).
static inline __attribute__((always_inline)) void camera_batch_make(const camera *c, uint64_t stream,
                                                                   camera_batch *b) {
    bool lens = c->kind != CAMERA_VIEWPORT && c->defocus_angle_degrees > 0.0f, shutter = camera_has_shutter(c);
    camera_batch_draws u;
    if (stream == RNG_SOBOL_STREAM) {
        camera_batch_sobol(b, lens, shutter, &u);
    } else { // PCG32: the film point's two draws, the lens point's two, the time's one, in camera_sample_ray's order
        uint64_t st[CAMERA_BATCH];
        for (int i = 0; i < CAMERA_BATCH; i++) {
            // rng_for_key: state 0 stepped (to the stream), plus the mixed key, stepped again.
            st[i] = (stream + rng_mix64(b->key[i] ^ (b->sample[i] + 0x2545f4914f6cdd1dULL))) *
                        6364136223846793005ULL +
                    stream;
        }
        batch_float(st, stream, u.jx);
        batch_float(st, stream, u.jy);
        if (lens) {
            batch_float(st, stream, u.u1);
            batch_float(st, stream, u.u2);
        }
        if (shutter) batch_float(st, stream, u.ut);
        for (int i = 0; i < CAMERA_BATCH; i++) b->r[i] = (rng){.state = st[i], .inc = stream};
    }
    float tx[CAMERA_BATCH], ty[CAMERA_BATCH], tz[CAMERA_BATCH];
    for (int i = 0; i < CAMERA_BATCH; i++) {
        float fx = (float)b->x[i] + u.jx[i], fy = (float)b->y[i] + u.jy[i];
        tx[i] = c->pixel00.x + (c->pixel_du.x * fx + c->pixel_dv.x * fy);
        ty[i] = c->pixel00.y + (c->pixel_du.y * fx + c->pixel_dv.y * fy);
        tz[i] = c->pixel00.z + (c->pixel_du.z * fx + c->pixel_dv.z * fy);
    }
    float ox[CAMERA_BATCH], oy[CAMERA_BATCH], oz[CAMERA_BATCH];
    if (c->kind == CAMERA_VIEWPORT) {
        for (int i = 0; i < CAMERA_BATCH; i++) {
            b->o[i] = v3(tx[i], ty[i], tz[i]);
            b->d[i] = v3(tx[i] - c->origin.x, ty[i] - c->origin.y, tz[i] - c->origin.z);
        }
    } else {
        for (int i = 0; i < CAMERA_BATCH; i++) {
            ox[i] = c->origin.x;
            oy[i] = c->origin.y;
            oz[i] = c->origin.z;
        }
        if (lens) { // sample_unit_disk, then the lens point
            float cs[CAMERA_BATCH], sn[CAMERA_BATCH];
            batch_sincos_turn(u.u2, cs, sn);
            for (int i = 0; i < CAMERA_BATCH; i++) {
                float rad = sqrtf(u.u1[i]), dx = rad * cs[i], dy = rad * sn[i];
                ox[i] = c->origin.x + (c->defocus_u.x * dx + c->defocus_v.x * dy);
                oy[i] = c->origin.y + (c->defocus_u.y * dx + c->defocus_v.y * dy);
                oz[i] = c->origin.z + (c->defocus_u.z * dx + c->defocus_v.z * dy);
            }
        }
        for (int i = 0; i < CAMERA_BATCH; i++) {
            b->o[i] = v3(ox[i], oy[i], oz[i]);
            b->d[i] = v3(tx[i] - ox[i], ty[i] - oy[i], tz[i] - oz[i]);
        }
    }
    if (shutter) { // rng_range(r, open, close), after the other draws
        for (int i = 0; i < CAMERA_BATCH; i++)
            b->time[i] = c->shutter_open + (c->shutter_close - c->shutter_open) * u.ut[i];
    } else {
        for (int i = 0; i < CAMERA_BATCH; i++) b->time[i] = c->shutter_open;
    }
}

#endif
