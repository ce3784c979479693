// envmap.h — an environment light: an equirectangular (latitude-longitude) HDR image around the scene, and
// the distribution that samples its directions in proportion to their brightness (pbrt's image infinite
// light, with a piecewise-constant lookup so that the sampling density matches the radiance exactly).
//
// Orientation: +y is up. A direction d has longitude phi = atan2(d.x, -d.z) (0 towards -z, increasing
// towards +x) and polar angle theta = acos(d.y) (0 straight up). Texel column u = (phi / 2 pi + 0.5) W, row
// v = theta / pi H: the image's centre looks towards -z, its top row is the zenith, its left and right
// edges are +z, and +x is three quarters of the way across. `rotate` turns the map about +y by that many
// degrees (counterclockwise seen from above: positive angles carry the centre from -z towards -x).
#ifndef GLINT_ENVMAP_H
#define GLINT_ENVMAP_H

#include "core/image_rgb.h"
#include "core/vec.h"

#include <stdbool.h>
#include <stddef.h>

/// The environment: the image (owned), a radiance scale, and the rotation about +y.
typedef struct envmap {
    image_rgb image;
    float scale;
    float rotate_cos, rotate_sin; ///< cos and sin of the rotation
} envmap;

/// An environment of image img (taken over), scaled by `scale`, turned `rotate_degrees` about +y.
envmap envmap_make(image_rgb img, float scale, float rotate_degrees);
/// Frees the image.
void envmap_free(envmap *e);
/// The radiance arriving from unit direction d (the texel d falls in, times the scale).
vec3 envmap_radiance(const envmap *e, vec3 d);

/// Directions of an environment sampled by brightness: a 2D piecewise-constant distribution over its texels,
/// each weighted by its luminance times the solid angle it covers (sin theta), as a marginal over rows and a
/// conditional over the columns of each row.
typedef struct envmap_sampler {
    float *row_cdf;   ///< H entries: probability of rows 0..v
    float *col_cdf;   ///< W * H entries: within row v, probability of columns 0..u
    float *texel_pdf; ///< W * H entries: probability of choosing the texel
    int width, height;
} envmap_sampler;

/// Builds the distribution of e; false when out of memory or when the map is black (nothing to sample).
bool envmap_sampler_build(envmap_sampler *s, const envmap *e);
/// Frees the distribution.
void envmap_sampler_release(envmap_sampler *s);
/// A direction drawn from the distribution with uniform numbers a, b: its unit vector *wi, its density per
/// unit solid angle *pdf, and the radiance from it. False (pdf 0) for a texel at a pole that covers no solid
/// angle.
bool envmap_sample(const envmap_sampler *s, const envmap *e, float a, float b, vec3 *wi, float *pdf, vec3 *radiance);
/// The density per unit solid angle with which envmap_sample draws unit direction d.
float envmap_pdf(const envmap_sampler *s, const envmap *e, vec3 d);

#endif
