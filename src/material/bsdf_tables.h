// bsdf_tables.h — directional albedos of the GGX lobes, for energy compensation (bsdf.c): tabulated by
// tools/make_bsdf_tables.c (deterministic: a stratified grid of samples, no random numbers) into
// bsdf_tables.c, which is committed with its generator.
#ifndef GLINT_BSDF_TABLES_H
#define GLINT_BSDF_TABLES_H

/// Nodes over cos(theta_o): mu_i = (i / (BSDF_TABLE_MU - 1))^2, closer near grazing where the albedos change fastest
/// (the first evaluated at 1e-3); looked up at sqrt(mu) (BSDF_TABLE_MU - 1).
#define BSDF_TABLE_MU 32
/// Nodes over perceptual roughness: r_j = j / (BSDF_TABLE_ROUGH - 1), alpha = mf_alpha(r_j).
#define BSDF_TABLE_ROUGH 32
/// Nodes over the relative index etap: etap_k = 3^(2k / (BSDF_TABLE_ETA - 1) - 1), from 1/3 to 3; the middle is 1.
#define BSDF_TABLE_ETA 33

/// E(mu, r): the albedo of the single-scattering GGX reflection lobe with Fresnel 1 (Kulla and Conty's E).
extern const float bsdf_table_conductor_e[BSDF_TABLE_ROUGH][BSDF_TABLE_MU];
/// E_avg(r) = 2 int E(mu, r) mu dmu: the lobe's hemispherical albedo.
extern const float bsdf_table_conductor_e_avg[BSDF_TABLE_ROUGH];
/// The albedo, reflection plus transmission with exact Fresnel, of the single-scattering rough dielectric
/// (Walter et al. 2007) seen from the side where the other medium's index over this one's is etap.
extern const float bsdf_table_dielectric_e[BSDF_TABLE_ETA][BSDF_TABLE_ROUGH][BSDF_TABLE_MU];
/// The albedo of the single-scattering GGX reflection lobe with Schlick's Fresnel from f0 is f0 A(mu, r) + B(mu, r)
/// (linear in f0): A weighs each reflection by 1 - (1 - wo.h)^5, B by (1 - wo.h)^5. With their hemispherical
/// averages, for pbr's specular layer over its base (bsdf.c, layer_albedo).
extern const float bsdf_table_schlick_a[BSDF_TABLE_ROUGH][BSDF_TABLE_MU], bsdf_table_schlick_a_avg[BSDF_TABLE_ROUGH];
extern const float bsdf_table_schlick_b[BSDF_TABLE_ROUGH][BSDF_TABLE_MU], bsdf_table_schlick_b_avg[BSDF_TABLE_ROUGH];

#endif
