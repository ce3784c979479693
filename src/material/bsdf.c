// bsdf.c — the BSDF of every material kind: the book's and the paper's materials through their own sampling
// (mat_scatter), and the microfacet materials: GGX reflection with Kulla–Conty multiple-scattering compensation
// (conductor; pbr's metal and specular layer), Walter et al.'s rough dielectric with its albedo divided out
// (rough_dielectric; pbr's transmission), and glTF 2.0's metallic-roughness mixture (pbr).
#include "material/bsdf.h"
#include "core/sampling.h"
#include "material/bsdf_tables.h"
#include "material/microfacet.h"

#include <float.h>
#include <math.h>

static const float pi = 3.14159265358979f, inv_pi = 0.318309886183791f;

// ---------------------------------------------------------------------------------------------
// The albedo tables, interpolated

// The cell of x in [0, n - 1] (clamped) and the position in it.
static inline int table_cell(float x, int n, float *frac) {
    if (!(x > 0.0f)) x = 0.0f;
    if (x > (float)(n - 1)) x = (float)(n - 1);
    int i = (int)x;
    if (i > n - 2) i = n - 2;
    *frac = x - (float)i;
    return i;
}

// E(mu, r) of the Fresnel-1 GGX reflection lobe, bilinear.
static float conductor_e(float rough, float mu) {
    float fr, fm;
    int j = table_cell(rough * (BSDF_TABLE_ROUGH - 1), BSDF_TABLE_ROUGH, &fr);
    int i = table_cell(sqrtf(mu) * (BSDF_TABLE_MU - 1), BSDF_TABLE_MU, &fm);
    const float *r0 = bsdf_table_conductor_e[j], *r1 = bsdf_table_conductor_e[j + 1];
    float a = r0[i] + (r0[i + 1] - r0[i]) * fm, b = r1[i] + (r1[i + 1] - r1[i]) * fm;
    return a + (b - a) * fr;
}

static float conductor_e_avg(float rough) {
    float fr;
    int j = table_cell(rough * (BSDF_TABLE_ROUGH - 1), BSDF_TABLE_ROUGH, &fr);
    const float *t = bsdf_table_conductor_e_avg;
    return t[j] + (t[j + 1] - t[j]) * fr;
}

// The rough dielectric's albedo (reflection + transmission) at (etap, r, mu), trilinear; etap in [1/3, 3].
static float dielectric_e(float etap, float rough, float mu) {
    float fe, fr, fm;
    float x = (logf(etap) / logf(3.0f) + 1.0f) * 0.5f * (BSDF_TABLE_ETA - 1);
    int k = table_cell(x, BSDF_TABLE_ETA, &fe);
    int j = table_cell(rough * (BSDF_TABLE_ROUGH - 1), BSDF_TABLE_ROUGH, &fr);
    int i = table_cell(sqrtf(mu) * (BSDF_TABLE_MU - 1), BSDF_TABLE_MU, &fm);
    float v[2];
    for (int s = 0; s < 2; s++) {
        const float *r0 = bsdf_table_dielectric_e[k + s][j], *r1 = bsdf_table_dielectric_e[k + s][j + 1];
        float a = r0[i] + (r0[i + 1] - r0[i]) * fm, b = r1[i] + (r1[i + 1] - r1[i]) * fm;
        v[s] = a + (b - a) * fr;
    }
    return v[0] + (v[1] - v[0]) * fe;
}

// A [ROUGH][MU] table, bilinear, and its [ROUGH] average, linear.
static float table2(const float t[BSDF_TABLE_ROUGH][BSDF_TABLE_MU], float rough, float mu) {
    float fr, fm;
    int j = table_cell(rough * (BSDF_TABLE_ROUGH - 1), BSDF_TABLE_ROUGH, &fr);
    int i = table_cell(sqrtf(mu) * (BSDF_TABLE_MU - 1), BSDF_TABLE_MU, &fm);
    float a = t[j][i] + (t[j][i + 1] - t[j][i]) * fm, b = t[j + 1][i] + (t[j + 1][i + 1] - t[j + 1][i]) * fm;
    return a + (b - a) * fr;
}

static float table1(const float t[BSDF_TABLE_ROUGH], float rough) {
    float fr;
    int j = table_cell(rough * (BSDF_TABLE_ROUGH - 1), BSDF_TABLE_ROUGH, &fr);
    return t[j] + (t[j + 1] - t[j]) * fr;
}

// Kulla and Conty's colour of the multiple-scattering lobe for a Fresnel whose hemispherical average is f_avg:
// the energy of the second and later bounces, F_avg^2 E_avg / (1 - F_avg (1 - E_avg)), per channel.
static vec3 ms_colour(vec3 f_avg, float e_avg) {
    vec3 one = v3s(1.0f);
    vec3 num = v3_scale(v3_mul(f_avg, f_avg), e_avg);
    vec3 den = v3_sub(one, v3_scale(f_avg, 1.0f - e_avg));
    return v3(num.x / den.x, num.y / den.y, num.z / den.z);
}

// The hemispherical average 2 int F mu dmu of Schlick's Fresnel from f0: f0 + (1 - f0) / 21.
static vec3 schlick_average(vec3 f0) { return v3_add(f0, v3_scale(v3_sub(v3s(1.0f), f0), 1.0f / 21.0f)); }

// ---------------------------------------------------------------------------------------------
// Frames

static inline vec3 to_local(const bsdf *b, vec3 w) { return v3(v3_dot(w, b->t), v3_dot(w, b->b), v3_dot(w, b->n)); }

static inline vec3 to_world(const bsdf *b, vec3 w) {
    return v3_add(v3_add(v3_scale(b->t, w.x), v3_scale(b->b, w.y)), v3_scale(b->n, w.z));
}

// The frame around unit n with t along `tangent`'s part in the plane (any direction when it has none).
static void frame(bsdf *b, vec3 n, vec3 tangent) {
    b->n = n;
    vec3 t = v3_sub(tangent, v3_scale(n, v3_dot(n, tangent)));
    float len2 = v3_len2(t);
    if (len2 > 1e-12f && isfinite(len2)) {
        b->t = v3_scale(t, 1.0f / sqrtf(len2));
        b->b = v3_cross(n, b->t);
    } else {
        v3_basis(n, &b->t, &b->b);
    }
}

// The channel of texture `tex` (-1: none, 1) at the site.
static float texture_channel(const texture *textures, int32_t tex, int channel, const bsdf_site *site) {
    if (tex < 0) return 1.0f;
    return v3_comp(texture_value(&textures[tex], site->u, site->v, site->p), channel);
}

// A tangent-space normal map's normal at the site, in world space: the texel's [0, 1] mapped to [-1, 1], x and y
// scaled by `scale` (glTF's normalTexture.scale), along the site's tangent and bitangent (n x tangent when none).
static vec3 mapped_normal(const texture *map, float scale, const bsdf_site *site, vec3 n) {
    vec3 c = texture_value(map, site->u, site->v, site->p);
    vec3 tn = v3((2.0f * c.x - 1.0f) * scale, (2.0f * c.y - 1.0f) * scale, 2.0f * c.z - 1.0f);
    vec3 t = site->tangent, bt = site->bitangent;
    if (!(v3_len2(t) > 0.0f)) {
        vec3 b2;
        v3_basis(n, &t, &b2);
    }
    t = v3_sub(t, v3_scale(n, v3_dot(n, t)));
    if (!(v3_len2(t) > 1e-12f)) return n;
    t = v3_unit(t);
    if (!(v3_len2(bt) > 0.0f)) bt = v3_cross(n, t);
    bt = v3_sub(bt, v3_add(v3_scale(n, v3_dot(n, bt)), v3_scale(t, v3_dot(t, bt))));
    if (!(v3_len2(bt) > 1e-12f)) bt = v3_cross(n, t);
    bt = v3_unit(bt);
    // The site's n faces the path; a back face sees the map's normal mirrored with it.
    vec3 m = v3_add(v3_add(v3_scale(t, tn.x), v3_scale(bt, tn.y)), v3_scale(n, tn.z));
    float len2 = v3_len2(m);
    if (!(len2 > 1e-12f) || !isfinite(len2) || !(v3_dot(m, n) > 0.0f)) return n;
    return v3_scale(m, 1.0f / sqrtf(len2));
}

void bsdf_init(bsdf *b, const material *m, const texture *textures, vec3 albedo, const bsdf_site *site) {
    b->m = m;
    // glTF multiplies the base colour texture by baseColorFactor (a constant base colour is the factor itself).
    b->base = m->kind == MAT_PBR && m->albedo_texture >= 0 ? v3_mul(albedo, m->base_factor) : albedo;
    b->front = site->front;
    b->compensate = true;
    b->metallic = b->transmission = 0.0f;
    b->f0_dielectric = 0.0f;
    b->ms_metal = b->ms_dielectric = v3s(0.0f);
    b->etap = 1.0f;
    b->rough = 0.0f;
    b->ax = b->ay = 1.0f;
    b->e_avg = 1.0f;
    vec3 n = site->n;
    if (m->kind == MAT_PBR && m->normal_texture >= 0)
        n = mapped_normal(&textures[m->normal_texture], m->normal_scale, site, n);
    frame(b, n, site->tangent);
    switch (m->kind) {
    case MAT_LAMBERTIAN: b->flags = BSDF_DIFFUSE | BSDF_REFLECTION; return;
    case MAT_PHONG: b->flags = BSDF_DIFFUSE | BSDF_DELTA | BSDF_REFLECTION; return;
    // The book's fuzzed metal has a density (mat_metal_pdf), so lights are sampled at it; a perfect mirror has none.
    case MAT_METAL: b->flags = (m->fuzz > 0.0f ? BSDF_GLOSSY : BSDF_DELTA) | BSDF_REFLECTION; return;
    case MAT_DIELECTRIC: b->flags = BSDF_DELTA | BSDF_REFLECTION | BSDF_TRANSMISSION; return;
    case MAT_DIFFUSE_LIGHT:
    case MAT_KIND_COUNT: b->flags = 0; return;
    case MAT_CONDUCTOR:
    case MAT_ROUGH_DIELECTRIC:
    case MAT_PBR: break;
    }
    float rough = m->roughness * texture_channel(textures, m->roughness_texture, 1, site);
    rough = rough < 0.0f ? 0.0f : rough > 1.0f ? 1.0f : rough;
    float alpha = mf_alpha(rough);
    b->rough = rough;
    b->ax = b->ay = alpha;
    b->e_avg = conductor_e_avg(rough);
    float ior = m->ior;
    // Dielectric interfaces beyond [1/3, 3] use the tables' last entries.
    b->etap = site->front ? ior : 1.0f / ior;
    if (m->kind == MAT_CONDUCTOR) {
        if (m->anisotropy > 0.0f) { // Burley's (Disney) stretch: the lobe is longer along t
            float aspect = sqrtf(1.0f - 0.9f * m->anisotropy);
            b->ax = fmaxf(alpha / aspect, MF_ALPHA_MIN);
            b->ay = fmaxf(alpha * aspect, MF_ALPHA_MIN);
        }
        vec3 f0 = m->fresnel == FRESNEL_SCHLICK_F0
                      ? m->f0
                      : v3(mf_fresnel_conductor1(1.0f, m->eta.x, m->k.x), mf_fresnel_conductor1(1.0f, m->eta.y, m->k.y),
                           mf_fresnel_conductor1(1.0f, m->eta.z, m->k.z));
        // The complex IOR's F_avg is taken as Schlick's from its f0: the multiple-scattering colour only.
        b->ms_metal = ms_colour(schlick_average(f0), b->e_avg);
        b->flags = BSDF_GLOSSY | BSDF_REFLECTION;
        return;
    }
    if (m->kind == MAT_ROUGH_DIELECTRIC) {
        b->flags = fabsf(b->etap - 1.0f) < 1e-5f ? BSDF_DELTA | BSDF_TRANSMISSION
                                                 : BSDF_GLOSSY | BSDF_REFLECTION | BSDF_TRANSMISSION;
        return;
    }
    // pbr
    b->metallic = m->metallic * texture_channel(textures, m->metallic_texture, 2, site);
    b->transmission = m->transmission * texture_channel(textures, m->transmission_texture, 0, site);
    b->metallic = fminf(fmaxf(b->metallic, 0.0f), 1.0f);
    b->transmission = fminf(fmaxf(b->transmission, 0.0f), 1.0f);
    float r0 = (ior - 1.0f) / (ior + 1.0f);
    b->f0_dielectric = r0 * r0;
    b->ms_metal = ms_colour(schlick_average(albedo), b->e_avg);
    b->ms_dielectric = ms_colour(schlick_average(v3s(b->f0_dielectric)), b->e_avg);
    b->layer_avg = b->f0_dielectric * table1(bsdf_table_schlick_a_avg, b->rough) + table1(bsdf_table_schlick_b_avg, b->rough);
    b->flags = BSDF_REFLECTION | BSDF_GLOSSY;
    if (b->metallic < 1.0f && b->transmission < 1.0f) b->flags |= BSDF_DIFFUSE;
    if (b->metallic < 1.0f && b->transmission > 0.0f)
        b->flags |= BSDF_TRANSMISSION | (fabsf(b->etap - 1.0f) < 1e-5f ? BSDF_DELTA : BSDF_GLOSSY);
}

// ---------------------------------------------------------------------------------------------
// GGX reflection with Kulla–Conty compensation (local frame: wo.z > 0)

// The probability of drawing the multiple-scattering lobe (cosine-distributed) rather than the visible normals:
// its share 1 - E(mu_o) of the Fresnel-1 energy.
static inline float ms_probability(const bsdf *b, vec3 wo) {
    return b->compensate ? 1.0f - conductor_e(b->rough, wo.z) : 0.0f;
}

// The single-scattering lobe without Fresnel, D G2 / (4 cos_o cos_i), at half vector h; and the multiple-
// scattering lobe's shape (1 - E(mu_o))(1 - E(mu_i)) / (pi (1 - E_avg)) into *ms (0 without compensation).
static float spec_shape(const bsdf *b, vec3 wo, vec3 wi, vec3 h, float *ms) {
    *ms = 0.0f;
    if (b->compensate && b->e_avg < 0.999999f)
        *ms = (1.0f - conductor_e(b->rough, wo.z)) * (1.0f - conductor_e(b->rough, wi.z)) / (pi * (1.0f - b->e_avg));
    return mf_d(h, b->ax, b->ay) * mf_g2(wo, wi, b->ax, b->ay) / (4.0f * wo.z * wi.z);
}

// The density of spec_sample's directions.
static float spec_pdf(const bsdf *b, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
    vec3 h = v3_unit(v3_add(wo, wi));
    float q = ms_probability(b, wo);
    float single = mf_g1(wo, b->ax, b->ay) * mf_d(h, b->ax, b->ay) / (4.0f * wo.z);
    return (1.0f - q) * single + q * wi.z * inv_pi;
}

// A reflection direction: the multiple-scattering lobe's (cosine) with probability ms_probability, else the mirror
// image of wo about a visible normal. False when it points below the surface.
static bool spec_sample(const bsdf *b, vec3 wo, rng *r, vec3 *wi) {
    float q = ms_probability(b, wo), u0 = rng_float(r), u1, u2;
    rng_float2(r, &u1, &u2);
    if (u0 < q) {
        float c, s, rad = sqrtf(u1);
        sincos_turn(u2, &c, &s);
        *wi = v3(rad * c, rad * s, sqrtf(fmaxf(0.0f, 1.0f - u1)));
    } else {
        *wi = mf_reflect(wo, mf_sample_visible(wo, b->ax, b->ay, u1, u2));
    }
    return wi->z > 0.0f;
}

// The conductor's Fresnel reflectance at cos_i per channel.
static vec3 conductor_reflectance(const material *m, float cos_i) {
    if (m->fresnel == FRESNEL_SCHLICK_F0) return mf_fresnel_schlick(m->f0, cos_i);
    return v3(mf_fresnel_conductor1(cos_i, m->eta.x, m->k.x), mf_fresnel_conductor1(cos_i, m->eta.y, m->k.y),
              mf_fresnel_conductor1(cos_i, m->eta.z, m->k.z));
}

static vec3 conductor_eval(const bsdf *b, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return v3s(0.0f);
    vec3 h = v3_unit(v3_add(wo, wi));
    float ms, single = spec_shape(b, wo, wi, h, &ms);
    return v3_add(v3_scale(conductor_reflectance(b->m, v3_dot(wo, h)), single), v3_scale(b->ms_metal, ms));
}

// ---------------------------------------------------------------------------------------------
// The rough dielectric (Walter et al. 2007), its albedo divided out (local frame: wo.z > 0)

// 1 / the single-scattering albedo at wo: the compensation that makes the interface lose no energy.
static inline float glass_compensation(const bsdf *b, vec3 wo) {
    if (!b->compensate) return 1.0f;
    float e = dielectric_e(b->etap, b->rough, wo.z);
    return e > 1e-3f ? 1.0f / e : 1.0f;
}

// The generalised half vector of a refraction from wo to wi (wi.z < 0), facing +z; false when the pair cannot
// be a refraction through a visible micro-normal.
static inline bool glass_half_transmit(const bsdf *b, vec3 wo, vec3 wi, vec3 *h) {
    vec3 m = v3_add(wo, v3_scale(wi, b->etap));
    float len2 = v3_len2(m);
    if (!(len2 > 0.0f)) return false;
    m = v3_scale(m, 1.0f / sqrtf(len2));
    if (m.z < 0.0f) m = v3_neg(m);
    *h = m;
    return v3_dot(wo, m) > 0.0f && v3_dot(wi, m) < 0.0f;
}

// f of the glass lobe; `tint` colours the transmission.
static vec3 glass_eval(const bsdf *b, vec3 wo, vec3 wi, vec3 tint) {
    if (!(wo.z > 0.0f) || wi.z == 0.0f) return v3s(0.0f);
    float ax = b->ax, ay = b->ay;
    if (wi.z > 0.0f) {
        vec3 h = v3_unit(v3_add(wo, wi));
        float f = mf_fresnel_dielectric(v3_dot(wo, h), b->etap);
        float v = f * mf_d(h, ax, ay) * mf_g2(wo, wi, ax, ay) / (4.0f * wo.z * wi.z);
        return v3s(v * glass_compensation(b, wo));
    }
    vec3 h;
    if (!glass_half_transmit(b, wo, wi, &h)) return v3s(0.0f);
    float oh = v3_dot(wo, h), ih = v3_dot(wi, h);
    float f = mf_fresnel_dielectric(oh, b->etap);
    float denom = ih + oh / b->etap;
    float v = (1.0f - f) * mf_d(h, ax, ay) * mf_g2(wo, wi, ax, ay) * fabsf(ih) * oh / (wo.z * fabsf(wi.z) * denom * denom);
    return v3_scale(tint, v * glass_compensation(b, wo));
}

static float glass_pdf(const bsdf *b, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f) || wi.z == 0.0f) return 0.0f;
    float ax = b->ax, ay = b->ay;
    if (wi.z > 0.0f) {
        vec3 h = v3_unit(v3_add(wo, wi));
        float f = mf_fresnel_dielectric(v3_dot(wo, h), b->etap);
        return f * mf_g1(wo, ax, ay) * mf_d(h, ax, ay) / (4.0f * wo.z);
    }
    vec3 h;
    if (!glass_half_transmit(b, wo, wi, &h)) return 0.0f;
    float oh = v3_dot(wo, h), ih = v3_dot(wi, h);
    float f = mf_fresnel_dielectric(oh, b->etap);
    float denom = ih + oh / b->etap;
    return (1.0f - f) * mf_visible_d(wo, h, ax, ay) * fabsf(ih) / (denom * denom);
}

// A direction of the glass lobe: a visible normal, then reflection with the Fresnel probability, else refraction.
// The weight is G2 / G1 (tinted for transmission), over the albedo where compensated.
static bool glass_sample(const bsdf *b, vec3 wo, vec3 tint, rng *r, bsdf_sample_record *s) {
    float u1, u2;
    rng_float2(r, &u1, &u2);
    float u3 = rng_float(r);
    float ax = b->ax, ay = b->ay;
    vec3 h = mf_sample_visible(wo, ax, ay, u1, u2);
    float oh = v3_dot(wo, h);
    float f = mf_fresnel_dielectric(oh, b->etap);
    vec3 wi;
    if (u3 < f) {
        wi = mf_reflect(wo, h);
        if (!(wi.z > 0.0f)) return false;
        s->pdf = f * mf_visible_d(wo, h, ax, ay) / (4.0f * oh);
        s->flags = BSDF_GLOSSY | BSDF_REFLECTION;
        s->weight = v3s(mf_g2(wo, wi, ax, ay) / mf_g1(wo, ax, ay) * glass_compensation(b, wo));
    } else {
        if (!mf_refract(wo, h, b->etap, &wi) || !(wi.z < 0.0f)) return false;
        float ih = v3_dot(wi, h), denom = ih + oh / b->etap;
        s->pdf = (1.0f - f) * mf_visible_d(wo, h, ax, ay) * fabsf(ih) / (denom * denom);
        s->flags = BSDF_GLOSSY | BSDF_TRANSMISSION;
        s->weight = v3_scale(tint, mf_g2(wo, wi, ax, ay) / mf_g1(wo, ax, ay) * glass_compensation(b, wo));
    }
    s->wi = wi;
    return s->pdf > 0.0f && isfinite(s->pdf);
}

// The albedo of pbr's dielectric specular layer at cos theta = mu: Schlick's single scattering (f0 A + B) and, with
// compensation, its multiple-scattering lobe's share ms (1 - E(mu)); at most 1.
static float layer_albedo(const bsdf *b, float mu) {
    float e = b->f0_dielectric * table2(bsdf_table_schlick_a, b->rough, mu) + table2(bsdf_table_schlick_b, b->rough, mu);
    if (b->compensate) e += b->ms_dielectric.x * (1.0f - conductor_e(b->rough, mu));
    return fminf(e, 1.0f);
}

// ---------------------------------------------------------------------------------------------
// pbr: glTF 2.0's metallic-roughness model (appendix B), with KHR_materials_transmission and _ior:
//   mix(fresnel_mix(ior, mix(diffuse, transmission, transmission weight), specular), metal, metallic)
// where the metal is the specular lobe times Schlick's Fresnel from the base colour and fresnel_mix weighs the
// specular lobe by Schlick's F from f0 = ((ior - 1) / (ior + 1))^2. The specification weighs the base by 1 - F at
// wo.h, which is not energy-conserving (a white base reflects up to 1.7 at grazing angles: more light than it
// gets); the base here gets what the layer does not reflect, by albedo scaling (Kulla and Conty 2017's layering,
// as Cycles' Principled BSDF and OpenPBR do): base / pi (1 - E_l(mu_o)) (1 - E_l(mu_i)) / (1 - E_l,avg), E_l the
// layer's albedo, so that a white base and the layer reflect exactly 1 (reciprocal, as the lobe must be). The
// transmission is the rough dielectric's lobe tinted by the base colour.

// The lobes' weights: metal, the opaque dielectric (specular layer over the Lambertian base) and glass.
static inline void pbr_weights(const bsdf *b, float *metal, float *opaque, float *glass) {
    *metal = b->metallic;
    *glass = (1.0f - b->metallic) * b->transmission;
    *opaque = (1.0f - b->metallic) * (1.0f - b->transmission);
}

// The probabilities of sampling the specular reflection, the diffuse base and the glass at wo.
static void pbr_lobe_probabilities(const bsdf *b, vec3 wo, float *spec, float *diffuse, float *glass) {
    float wm, wd, wg;
    pbr_weights(b, &wm, &wd, &wg);
    float fs = mf_fresnel_schlick(v3s(b->f0_dielectric), wo.z).x;
    float s = wm + wd * fs, d = wd * (1.0f - fs), g = wg, sum = s + d + g;
    *spec = s / sum;
    *diffuse = d / sum;
    *glass = g / sum;
}

static vec3 pbr_eval(const bsdf *b, vec3 wo, vec3 wi) {
    float wm, wd, wg;
    pbr_weights(b, &wm, &wd, &wg);
    vec3 f = v3s(0.0f);
    if (wo.z > 0.0f && wi.z > 0.0f && (wm > 0.0f || wd > 0.0f)) {
        vec3 h = v3_unit(v3_add(wo, wi));
        float c = v3_dot(wo, h), ms, single = spec_shape(b, wo, wi, h, &ms);
        if (wm > 0.0f) {
            vec3 metal = v3_add(v3_scale(mf_fresnel_schlick(b->base, c), single), v3_scale(b->ms_metal, ms));
            f = v3_add(f, v3_scale(metal, wm));
        }
        if (wd > 0.0f) {
            float fd = mf_fresnel_schlick(v3s(b->f0_dielectric), c).x;
            vec3 layer = v3_add(v3s(fd * single), v3_scale(b->ms_dielectric, ms));
            // The layer's hemispherical albedo: its single scattering's, and the multiple-scattering lobe's share.
            float avg = fminf(b->layer_avg + (b->compensate ? b->ms_dielectric.x * (1.0f - b->e_avg) : 0.0f), 1.0f);
            float under = avg < 1.0f ? (1.0f - layer_albedo(b, wo.z)) * (1.0f - layer_albedo(b, wi.z)) / (1.0f - avg)
                                     : 0.0f;
            vec3 opaque = v3_add(layer, v3_scale(b->base, under * inv_pi));
            f = v3_add(f, v3_scale(opaque, wd));
        }
    }
    if (wg > 0.0f && !(b->flags & BSDF_DELTA)) f = v3_add(f, v3_scale(glass_eval(b, wo, wi, b->base), wg));
    return f;
}

static float pbr_pdf(const bsdf *b, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f)) return 0.0f;
    float ps, pd, pg, pdf = 0.0f;
    pbr_lobe_probabilities(b, wo, &ps, &pd, &pg);
    if (ps > 0.0f) pdf += ps * spec_pdf(b, wo, wi);
    if (pd > 0.0f && wi.z > 0.0f) pdf += pd * wi.z * inv_pi;
    if (pg > 0.0f && !(b->flags & BSDF_DELTA)) pdf += pg * glass_pdf(b, wo, wi);
    return pdf;
}

static bool pbr_sample(const bsdf *b, vec3 wo, rng *r, bsdf_sample_record *s) {
    float ps, pd, pg;
    pbr_lobe_probabilities(b, wo, &ps, &pd, &pg);
    float u = rng_float(r);
    vec3 wi;
    if (u < pg) {
        if (b->flags & BSDF_DELTA) { // IOR 1: the glass passes the ray straight on, tinted
            float wm, wd, wg;
            pbr_weights(b, &wm, &wd, &wg);
            s->wi = v3_neg(wo);
            s->weight = v3_scale(b->base, wg / pg);
            s->pdf = 0.0f;
            s->flags = BSDF_DELTA | BSDF_TRANSMISSION;
            return true;
        }
        bsdf_sample_record g;
        if (!glass_sample(b, wo, b->base, r, &g)) return false;
        wi = g.wi;
    } else if (u < pg + pd) {
        float u1, u2, c, sn;
        rng_float2(r, &u1, &u2);
        float rad = sqrtf(u1);
        sincos_turn(u2, &c, &sn);
        wi = v3(rad * c, rad * sn, sqrtf(fmaxf(0.0f, 1.0f - u1)));
        if (!(wi.z > 0.0f)) return false;
    } else if (!spec_sample(b, wo, r, &wi)) {
        return false;
    }
    s->wi = wi;
    s->pdf = pbr_pdf(b, wo, wi);
    if (!(s->pdf > 0.0f) || !isfinite(s->pdf)) return false;
    s->weight = v3_scale(pbr_eval(b, wo, wi), fabsf(wi.z) / s->pdf);
    s->flags = (wi.z > 0.0f ? BSDF_REFLECTION : BSDF_TRANSMISSION) | (u < pg + pd && u >= pg ? BSDF_DIFFUSE : BSDF_GLOSSY);
    return true;
}

// ---------------------------------------------------------------------------------------------
// The interface

vec3 bsdf_eval(const bsdf *b, vec3 wo, vec3 wi) {
    const material *m = b->m;
    switch (m->kind) {
    case MAT_LAMBERTIAN:
    case MAT_PHONG: {
        if (!(v3_dot(wo, b->n) > 0.0f) || !(v3_dot(wi, b->n) > 0.0f)) return v3s(0.0f);
        float diffuse = m->kind == MAT_PHONG ? 1.0f - m->reflective : 1.0f;
        return v3_scale(b->base, diffuse * inv_pi);
    }
    case MAT_METAL: { // f cos = albedo times the sampling density: the book's weight, albedo, is f cos / pdf
        float c = v3_dot(wi, b->n);
        if (m->fuzz == 0.0f || !(v3_dot(wo, b->n) > 0.0f) || !(c > 0.0f)) return v3s(0.0f);
        return v3_scale(b->base, mat_metal_pdf(v3_reflect(v3_neg(wo), b->n), m->fuzz, wi) / c);
    }
    case MAT_DIELECTRIC:
    case MAT_DIFFUSE_LIGHT:
    case MAT_KIND_COUNT: return v3s(0.0f);
    case MAT_CONDUCTOR: return conductor_eval(b, to_local(b, wo), to_local(b, wi));
    case MAT_ROUGH_DIELECTRIC:
        if (b->flags & BSDF_DELTA) return v3s(0.0f);
        return glass_eval(b, to_local(b, wo), to_local(b, wi), b->base);
    case MAT_PBR: return pbr_eval(b, to_local(b, wo), to_local(b, wi));
    }
    return v3s(0.0f);
}

float bsdf_pdf(const bsdf *b, vec3 wo, vec3 wi) {
    const material *m = b->m;
    switch (m->kind) {
    case MAT_LAMBERTIAN:
    case MAT_PHONG: {
        float c = v3_dot(wi, b->n);
        if (!(v3_dot(wo, b->n) > 0.0f) || !(c > 0.0f)) return 0.0f;
        return (m->kind == MAT_PHONG ? 1.0f - m->reflective : 1.0f) * c * inv_pi;
    }
    case MAT_METAL: // the directions below the surface are absorbed: no density there
        if (m->fuzz == 0.0f || !(v3_dot(wo, b->n) > 0.0f) || !(v3_dot(wi, b->n) > 0.0f)) return 0.0f;
        return mat_metal_pdf(v3_reflect(v3_neg(wo), b->n), m->fuzz, wi);
    case MAT_DIELECTRIC:
    case MAT_DIFFUSE_LIGHT:
    case MAT_KIND_COUNT: return 0.0f;
    case MAT_CONDUCTOR: return spec_pdf(b, to_local(b, wo), to_local(b, wi));
    case MAT_ROUGH_DIELECTRIC:
        if (b->flags & BSDF_DELTA) return 0.0f;
        return glass_pdf(b, to_local(b, wo), to_local(b, wi));
    case MAT_PBR: return pbr_pdf(b, to_local(b, wo), to_local(b, wi));
    }
    return 0.0f;
}

bool bsdf_sample(const bsdf *b, vec3 wo, rng *r, bsdf_sample_record *s) {
    const material *m = b->m;
    if (m->kind < MAT_DIFFUSE_LIGHT) {
        // The book's and the paper's materials, drawing their random numbers as the path tracer always has.
        scatter_event ev;
        if (!mat_scatter(m, b->base, v3_neg(wo), b->n, b->front, r, &ev)) return false;
        unsigned lobe = ev.diffuse ? BSDF_DIFFUSE : m->kind == MAT_METAL && m->fuzz > 0.0f ? BSDF_GLOSSY : BSDF_DELTA;
        s->wi = ev.dir;
        s->weight = ev.weight;
        s->pdf = lobe == BSDF_DELTA ? 0.0f : bsdf_pdf(b, wo, ev.dir);
        // A fuzzed metal's direction drawn at its cone's edge, where the density is unbounded, can land just
        // outside it by rounding, where bsdf_pdf says 0: what it finds is then its own (MIS weight 1).
        if (lobe == BSDF_GLOSSY && !(s->pdf > 0.0f)) s->pdf = FLT_MAX;
        s->flags = (ev.transmitted ? BSDF_TRANSMISSION : BSDF_REFLECTION) | lobe;
        return true;
    }
    vec3 lo = to_local(b, wo);
    if (!(lo.z > 0.0f)) return false; // a shading normal facing away from the path: absorbed
    switch (m->kind) {
    case MAT_CONDUCTOR: {
        vec3 wi;
        if (!spec_sample(b, lo, r, &wi)) return false;
        s->pdf = spec_pdf(b, lo, wi);
        if (!(s->pdf > 0.0f) || !isfinite(s->pdf)) return false;
        s->weight = v3_scale(conductor_eval(b, lo, wi), wi.z / s->pdf);
        s->wi = to_world(b, wi);
        s->flags = BSDF_GLOSSY | BSDF_REFLECTION;
        return true;
    }
    case MAT_ROUGH_DIELECTRIC:
        if (b->flags & BSDF_DELTA) { // IOR 1: no interface at all
            s->wi = v3_neg(wo);
            s->weight = b->base;
            s->pdf = 0.0f;
            s->flags = BSDF_DELTA | BSDF_TRANSMISSION;
            return true;
        }
        if (!glass_sample(b, lo, b->base, r, s)) return false;
        s->wi = to_world(b, s->wi);
        return true;
    case MAT_PBR:
        if (!pbr_sample(b, lo, r, s)) return false;
        s->wi = to_world(b, s->wi);
        return true;
    default: return false;
    }
}

bsdf_whitted bsdf_whitted_view(const bsdf *b, float cos_o) {
    const material *m = b->m;
    bsdf_whitted w = {v3s(0.0f), v3s(0.0f), false, v3s(1.0f)};
    float c = cos_o < 0.0f ? 0.0f : cos_o > 1.0f ? 1.0f : cos_o;
    switch (m->kind) {
    case MAT_CONDUCTOR: w.mirror = conductor_reflectance(m, c); break;
    case MAT_ROUGH_DIELECTRIC:
        w.refracts = true;
        w.tint = b->base;
        break;
    case MAT_PBR: {
        float wm, wd, wg;
        pbr_weights(b, &wm, &wd, &wg);
        float fd = mf_fresnel_schlick(v3s(b->f0_dielectric), c).x;
        w.mirror = v3_add(v3_scale(mf_fresnel_schlick(b->base, c), wm), v3s((wd + wg) * fd));
        w.diffuse = v3_scale(b->base, wd * (1.0f - layer_albedo(b, c)));
        break;
    }
    default: w.diffuse = b->base; break;
    }
    return w;
}
