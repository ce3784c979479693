// replay.c — the traversal alone, against Embree on the very same rays: records the rays of diffuse paths
// through a scene (camera rays and Lambertian bounces, as the path tracer makes them), then times glint's
// closest-hit query over them, and, when built with Embree 3, rtcIntersect1 over the same rays and the same
// world-space triangles. A render's rays per second mix traversal with shading; this separates them.
//
// usage: replay SCENE.json [--rays N] [--depth D] [--every K] [--reps R]
//   N rays (default 1000000) of paths of at most D rays (default 8) from every K-th pixel (default 1) in scan
//   order, one sample a pixel, wrapping around; each timing is the best of R passes (default 5) over all of
//   them, on one thread. Prints one line:
//   replay: N rays (H% hit), glint G ns/ray [, embree E ns/ray, glint/embree speed S, hit or miss agree A%]
// Exit status 1 when glint's replay does not find exactly the hits it recorded (the traversal is deterministic),
// or on bad input. Meshes and quads only for Embree (a scene with spheres is timed for glint alone).
#include "glint.h"
#include "accel/accel.h"
#include "core/clock.h"
#include "core/sampling.h"
#include "integrator/spawn.h"
#include "material/scatter.h"
#include "render/frame.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef GLINT_REPLAY_EMBREE
#include <embree3/rtcore.h>
#endif

typedef struct recorded {
    ray r;
    hit h;
    bool found;
} recorded;

// The rays of diffuse paths: each hit scatters as a Lambertian surface does (its shading normal), offset as the
// path tracer offsets; a path ends when it escapes or after `depth` rays.
static size_t record(const glint_scene *s, const accel *a, recorded *out, size_t n, int depth, uint64_t every) {
    size_t k = 0;
    int w = s->settings.width, h = s->settings.height;
    camera cam = s->camera;
    camera_prepare(&cam, w, h);
    uint64_t pixels = (uint64_t)w * (uint64_t)h;
    for (uint64_t visit = 0; k < n; visit += every) {
        uint64_t p = visit % pixels;
        rng g = rng_for_sample(s->settings.seed, p, visit / pixels);
        ray cur = camera_sample_ray(&cam, (int)(p % (uint64_t)w), (int)(p / (uint64_t)w), &g);
        cur.d = v3_unit(cur.d);
        for (int d = 0; d < depth && k < n; d++) {
            recorded *rec = &out[k++];
            rec->r = cur;
            rec->found = accel_intersect(a, &cur, &rec->h);
            if (!rec->found) break;
            surface sf = surface_at(s, &cur, &rec->h);
            spawn_point sp = spawn_point_of(s, &sf);
            cur = spawn_ray(&sp, mat_lambertian_dir(sf.n, sample_sphere_uniform(&g)), 0.0f, INFINITY);
        }
    }
    return k;
}

// Best of `reps` passes of glint's query over the rays, in ns a ray; *mismatches counts rays whose hit differs
// from the recorded one.
static double time_glint(const accel *a, const recorded *rec, size_t n, int reps, size_t *mismatches) {
    double best = INFINITY;
    *mismatches = 0;
    for (int rep = 0; rep < reps; rep++) {
        size_t bad = 0;
        double t0 = clock_seconds();
        for (size_t i = 0; i < n; i++) {
            hit h;
            bool found = accel_intersect(a, &rec[i].r, &h);
            bad += found != rec[i].found || (found && memcmp(&h, &rec[i].h, sizeof h) != 0);
        }
        double t = clock_seconds() - t0;
        best = t < best ? t : best;
        *mismatches = bad;
    }
    return best * 1e9 / (double)n;
}

#ifdef GLINT_REPLAY_EMBREE
// Adds triangles (positions, 3 indices each) as one Embree geometry of the scene's build quality.
static bool add_triangles(RTCDevice dev, RTCScene scn, const vec3 *pos, size_t np, const int32_t *idx, size_t stride,
                          size_t nt) {
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), np);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt);
    if (!vb || !ib) return false;
    for (size_t i = 0; i < np; i++) memcpy(&vb[3 * i], &pos[i], 3 * sizeof(float));
    for (size_t i = 0; i < nt; i++)
        for (int c = 0; c < 3; c++) ib[3 * i + (size_t)c] = (unsigned)idx[stride * i + (size_t)c];
    rtcCommitGeometry(g);
    rtcAttachGeometry(scn, g);
    rtcReleaseGeometry(g);
    return true;
}

// The scene's quads and mesh instances, in world space, as Embree triangles; false for anything else.
static bool embree_scene(const glint_scene *s, RTCDevice dev, RTCScene scn) {
    if (s->sphere_count || s->moving_sphere_count) return false;
    for (size_t i = 0; i < s->quad_count; i++) {
        static const int32_t idx[6] = {0, 1, 2, 0, 2, 3}; // quad_intersect's two triangles
        if (!add_triangles(dev, scn, s->quads[i].p, 4, idx, 3, 2)) return false;
    }
    for (size_t i = 0; i < s->instance_count; i++) {
        const instance *in = &s->instances[i];
        if (in->kind != INSTANCE_MESH || in->motion) return false;
        const mesh *m = &s->meshes[in->index].geometry;
        vec3 *world = malloc((m->position_count ? m->position_count : 1) * sizeof *world);
        if (!world) return false;
        for (size_t k = 0; k < m->position_count; k++) world[k] = mat4_apply_point(&in->xf.m, m->positions[k]);
        bool ok = add_triangles(dev, scn, world, m->position_count, m->triangles[0].v,
                                sizeof(mesh_triangle) / sizeof(int32_t), m->triangle_count);
        free(world);
        if (!ok) return false;
    }
    rtcSetSceneBuildQuality(scn, RTC_BUILD_QUALITY_HIGH);
    rtcCommitScene(scn);
    return rtcGetDeviceError(dev) == RTC_ERROR_NONE;
}

// Best of `reps` passes of rtcIntersect1 over the rays, in ns a ray; *agree counts rays that hit or miss as
// glint's did.
static double time_embree(RTCScene scn, const recorded *rec, size_t n, int reps, size_t *agree) {
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    double best = INFINITY;
    for (int rep = 0; rep < reps; rep++) {
        size_t same = 0;
        double t0 = clock_seconds();
        for (size_t i = 0; i < n; i++) {
            const ray *r = &rec[i].r;
            struct RTCRayHit rh = {.ray = {.org_x = r->o.x, .org_y = r->o.y, .org_z = r->o.z, .tnear = r->tmin,
                                           .dir_x = r->d.x, .dir_y = r->d.y, .dir_z = r->d.z, .tfar = r->tmax,
                                           .mask = ~0u},
                                   .hit = {.geomID = RTC_INVALID_GEOMETRY_ID}};
            rtcIntersect1(scn, &ctx, &rh);
            same += (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) == rec[i].found;
        }
        double t = clock_seconds() - t0;
        best = t < best ? t : best;
        *agree = same;
    }
    return best * 1e9 / (double)n;
}
#endif

static long arg_long(int argc, char **argv, int *i, long lo, long hi) {
    char *end;
    long v = *i + 1 < argc ? strtol(argv[*i + 1], &end, 10) : lo - 1;
    if (*i + 1 >= argc || *end || v < lo || v > hi) {
        fprintf(stderr, "replay: %s needs a number in [%ld, %ld]\n", argv[*i], lo, hi);
        exit(2);
    }
    ++*i;
    return v;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: replay SCENE.json [--rays N] [--depth D] [--every K] [--reps R]\n");
        return 2;
    }
    size_t n = 1000000;
    int depth = 8, reps = 5;
    uint64_t every = 1;
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "--rays")) n = (size_t)arg_long(argc, argv, &i, 1, 100000000);
        else if (!strcmp(argv[i], "--depth")) depth = (int)arg_long(argc, argv, &i, 1, 1000);
        else if (!strcmp(argv[i], "--every")) every = (uint64_t)arg_long(argc, argv, &i, 1, 1000000);
        else if (!strcmp(argv[i], "--reps")) reps = (int)arg_long(argc, argv, &i, 1, 1000);
        else {
            fprintf(stderr, "replay: unknown option %s\n", argv[i]);
            return 2;
        }
    }
    glint_scene *s;
    glint_error err;
    if (scene_file_load(argv[1], 1, &s, &err) != GLINT_OK) {
        fprintf(stderr, "replay: %s\n", err.message);
        return 1;
    }
    accel *a = frame_accel_build(s, &(accel_build_options){.threads = 1}, &err);
    recorded *rec = a ? malloc(n * sizeof *rec) : NULL;
    if (!rec) {
        fprintf(stderr, "replay: %s\n", a ? "out of memory" : err.message);
        accel_free(a);
        scene_free(s);
        return 1;
    }
    n = record(s, a, rec, n, depth, every);
    size_t mismatches, hits = 0;
    for (size_t i = 0; i < n; i++) hits += rec[i].found;
    double g = time_glint(a, rec, n, reps, &mismatches);
    printf("replay: %zu rays (%.1f%% hit), glint %.1f ns/ray", n, 100.0 * (double)hits / (double)n, g);
#ifdef GLINT_REPLAY_EMBREE
    RTCDevice dev = rtcNewDevice("threads=1");
    RTCScene scn = dev ? rtcNewScene(dev) : NULL;
    if (scn && embree_scene(s, dev, scn)) {
        size_t agree = 0; // gcc -O3 cannot see that time_embree always sets it
        double e = time_embree(scn, rec, n, reps, &agree);
        printf(", embree %.1f ns/ray, glint/embree speed %.3f, hit or miss agree %.3f%%", e, e / g,
               100.0 * (double)agree / (double)n);
    } else {
        printf(", embree: not this scene (meshes and quads only)");
    }
    if (scn) rtcReleaseScene(scn);
    if (dev) rtcReleaseDevice(dev);
#endif
    printf("\n");
    if (mismatches) fprintf(stderr, "replay: %zu rays found other hits than when recorded\n", mismatches);
    free(rec);
    accel_free(a);
    scene_free(s);
    return mismatches ? 1 : 0;
}
