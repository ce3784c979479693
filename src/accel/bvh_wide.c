// bvh_wide.c — the out-of-line half of the wide traversal step (bvh_wide.h): a packet of primitives tested one at a
// time (bvh_packet_hit), and the instances among them entered through their mesh's BVH by the wide traversal
// (blas_traverse, bvh_prim.h). The recursion through instances, wide_step -> bvh_packet_hit -> blas_traverse ->
// wide_run, thus stays within bvh_wide.h and this file; the traversals that include bvh_wide.h only call down.
#include "accel/bvh_prim.h"
#include "accel/bvh_wide.h"

// Each primitive of the packet in turn (prim_hit), an any-hit query stopping at the first hit.
__attribute__((noinline)) hit bvh_packet_hit(const bvh *b, const bvh_index_packet *p, const ray *r, tri_cache *tc,
                                             hit best, uint32_t inst_id, bool any, trav_mode mode, bool *hit_any) {
    *hit_any = false;
    for (uint32_t k = 0; k < p->h.count; k++) {
        if (!prim_hit(b, p->h.kind, p->prim[k], HIT_NO_INSTANCE, r, tc, &best, inst_id, any, mode)) continue;
        *hit_any = true;
        if (any) break;
    }
    return best;
}

// An instance's BLAS (bvh_prim.h), by the path of the wide traversal that entered it.
static bool blas_traverse(const bvh *blas, const ray *r, hit *best, uint32_t inst_id, bool any, trav_mode mode) {
    switch (mode) {
    case MODE_WIDE_SIMD: // a mesh's BVH holds only triangles
        if (blas->triangles_only) return wide_run(blas, r, best, inst_id, any, BVH_SIMD, LEAVES_TRIANGLES, NULL);
        return wide_run(blas, r, best, inst_id, any, BVH_SIMD, LEAVES_ANY, NULL);
    case MODE_WIDE_SCALAR: return wide_run(blas, r, best, inst_id, any, false, LEAVES_ANY, NULL);
    case MODE_BINARY: break; // the binary BVH's instances: bvh2_traverse.c
    }
    return false;
}
