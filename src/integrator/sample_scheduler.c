// sample_scheduler.c — the sample scheduler's choices made once per tile pass (its loops are inline, in
// sample_scheduler.h and sample_stream.h).
#include "integrator/sample_scheduler.h"

// Whether the stream loop traces its camera rays as packets (accel_intersect_coherent): in a BVH of triangles and
// quads, unless its streams are traversed together (accel_interleaves), the tile pass takes fewer than
// SCHEDULER_PACKET_SAMPLES samples a pixel and the tree has more leaf packets than the image has pixels. Then a
// batch's sixteen rays, from several pixels, spread over several leaves, and the stream traces them faster (bunny1m
// at 400x300 in passes of 1, 1, 2, 4, 8 samples, 1.3 leaves a pixel: packets 0.970; the 500k bunny, 0.6: 1.050). In
// passes of 16 samples a batch is one pixel's rays: packets 1.145 on the dragon, 1.13 on bunny1m, 1.10 on engine-2m.
bool scheduler_stream_packets(const integrator *it, int samples) {
    if (!accel_coherent(it->accel)) return false;
    if (!accel_interleaves(it->accel) || samples >= SCHEDULER_PACKET_SAMPLES) return true;
    accel_stats st;
    accel_get_stats(it->accel, &st);
    const render_settings *rs = &it->scene->settings;
    return st.leaves < (uint64_t)rs->width * (uint64_t)rs->height;
}
