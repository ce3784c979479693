// texture.h — colours that vary over a surface: solid, 3D checker, Perlin noise (plain, turbulence, marble)
// and bilinearly filtered image textures ("Ray Tracing: The Next Week", ch. 4-5).
#ifndef GLINT_TEXTURE_H
#define GLINT_TEXTURE_H

#include "core/vec.h"
#include "core/image_rgb.h"

#include <stdbool.h>
#include <stdint.h>

typedef enum texture_kind {
    TEX_SOLID,   ///< one colour
    TEX_CHECKER, ///< 3D checker of cubes of side `scale`, colours `even` and `odd`
    TEX_NOISE,   ///< Perlin noise of kind `noise`, times `color`
    TEX_IMAGE    ///< an image over (u, v) in [0,1]^2, repeated, v = 1 at the top row
} texture_kind;

typedef enum noise_kind {
    NOISE_PLAIN,      ///< 0.5 (1 + noise(scale p))
    NOISE_TURBULENCE, ///< turb(scale p, depth)
    NOISE_MARBLE,     ///< 0.5 (1 + sin(scale p.z + 10 turb(p, depth))), book 1's and book 2's text's marble
    NOISE_MARBLE_SCALED ///< 0.5 (1 + sin(s.z + 10 turb(s, depth))), s = scale p: book 2's program (2024)
} noise_kind;

/// How an image texture is looked up: bilinear between the four nearest texel centres, or the texel that
/// holds (u, v) (book 2's program).
typedef enum texture_filter { FILTER_BILINEAR, FILTER_NEAREST } texture_filter;

/// Perlin's lattice tables: random unit gradients and three permutations, built once from a seed.
typedef struct perlin {
    vec3 gradient[256];
    uint8_t perm_x[256], perm_y[256], perm_z[256];
} perlin;

/// A texture. Image and noise textures own heap memory: release with texture_free().
typedef struct texture {
    texture_kind kind;
    vec3 color;       ///< solid: the colour; noise: multiplies the noise value
    vec3 even, odd;   ///< checker colours: even when floor(x/scale) + floor(y/scale) + floor(z/scale) is even
    float scale;      ///< checker: cube side; noise: frequency
    noise_kind noise; ///< noise: which function
    int depth;        ///< noise: octaves of turbulence
    perlin *perlin;   ///< noise: owned tables
    image_rgb image;  ///< image: owned linear RGB pixels (and alpha, when the image has it)
    texture_filter filter; ///< image: how texels are looked up
} texture;

/// A solid colour.
texture texture_solid(vec3 color);
/// A 3D checker of cubes of side `scale` (> 0).
texture texture_checker(float scale, vec3 even, vec3 odd);
/// A Perlin noise texture; the tables are a pure function of `seed`. False when out of memory.
bool texture_noise(noise_kind kind, float scale, int depth, vec3 color, uint64_t seed, texture *out);
/// A Perlin noise texture with the given tables (copied), e.g. those a published program drew. False when out
/// of memory.
bool texture_noise_tables(noise_kind kind, float scale, int depth, vec3 color, const perlin *tables, texture *out);
/// An image texture that takes ownership of img's pixels.
texture texture_image(image_rgb img, texture_filter filter);
/// Releases what the texture owns and makes it a black solid texture.
void texture_free(texture *t);

/// The texture's linear RGB value at surface coordinates (u, v) and point p. Image textures repeat outside
/// [0, 1]^2 and are looked up as their filter says.
vec3 texture_value(const texture *t, float u, float v, vec3 p);

/// The texture's coverage (alpha) at (u, v), looked up as texture_value looks up colours: an image texture's
/// alpha plane, 1 for an image without one and for every other kind (alpha masks, material.alpha_cutoff).
float texture_alpha(const texture *t, float u, float v);

/// Fills the tables from `seed` (deterministic, no shared state).
void perlin_init(perlin *pn, uint64_t seed);
/// Perlin gradient noise at p, in about [-1, 1]; 0 for non-finite p.
float perlin_noise(const perlin *pn, vec3 p);
/// |sum over depth octaves of noise(2^i p) / 2^i|.
float perlin_turbulence(const perlin *pn, vec3 p, int depth);

#endif
