// sample_scheduler.c — the sample scheduler's choices made once per tile pass (its loops are inline, in
// sample_scheduler.h and sample_stream.h).
#include "integrator/sample_scheduler.h"

// Whether the stream loop traces its camera rays as packets (accel_intersect_coherent): in a BVH of triangles and
// quads, unless its streams are traversed together (accel_interleaves) and it has more leaf packets than the image
// has pixels. Then a pixel's sixteen rays spread over several leaves, and the stream traces them faster (bunny1m at
// 400x300, 1.3 leaves a pixel: packets 0.970; the 500k bunny, 0.6: 1.050; docs/benchmarks.md).
bool scheduler_stream_packets(const integrator *it) {
    if (!accel_coherent(it->accel)) return false;
    if (!accel_interleaves(it->accel)) return true;
    accel_stats st;
    accel_get_stats(it->accel, &st);
    const render_settings *rs = &it->scene->settings;
    return st.leaves < (uint64_t)rs->width * (uint64_t)rs->height;
}
