// tri_split.h — pre-splitting of long, slanted triangles for the BVH build (private to src/accel): a triangle
// whose box is far larger than the triangle itself (a sliver across a cylinder, a long diagonal strip) is
// entered by every ray that crosses its box; cut into pieces along its box's longest axis, each piece gets the
// box of the part of the triangle in it, and the build places the pieces as separate references to the same
// triangle (Karras and Aila 2013, "early split clipping"). The triangle test is unchanged: only boxes shrink.
#ifndef GLINT_TRI_SPLIT_H
#define GLINT_TRI_SPLIT_H

#include "geometry/mesh.h"
#include "geometry/transform.h"

#include <stdbool.h>

/// The most halvings of one triangle: at most 1 << TRI_SPLIT_MAX_LEVELS pieces.
enum { TRI_SPLIT_MAX_LEVELS = 3 };

/// How many times triangle (p0, p1, p2) asks to be halved, 0 to TRI_SPLIT_MAX_LEVELS, by how far its box's half
/// area exceeds its own area: 0 for the triangles of an evenly tessellated surface (an equilateral triangle's box
/// has at most 4.6 times its area, whatever its orientation), 0 for degenerate ones.
int tri_split_levels(vec3 p0, vec3 p1, vec3 p2);

/// Whether mesh m is one whose typical triangle is long and slanted: at least half of up to TRI_SPLIT_SAMPLES of its
/// triangles, evenly spaced, ask for a split (tri_split_levels). Only such meshes are pre-split: on meshes where a
/// minority of triangles are thin (a scan's slivers, a CAD model's fans) the pieces cost more leaves than their
/// smaller boxes save (docs/architecture.md, "Pre-splitting long, slanted triangles").
bool tri_split_mesh_wants(const mesh *m);
/// Triangles tri_split_mesh_wants looks at, at most.
enum { TRI_SPLIT_SAMPLES = 4096 };

/// Cuts triangle (p0, p1, p2) `levels` times (each piece halved across the longest axis of its box) and writes
/// the exact bounds of each non-empty piece, rounded outwards to float, into out (room for 1 << levels);
/// returns how many. Together the boxes hold every point of the triangle.
int tri_split_bounds(vec3 p0, vec3 p1, vec3 p2, int levels, bounds3 *out);

/// The bounds of the part of triangle (p0, p1, p2) inside the box [lo, hi] (clipped in double, rounded outwards to
/// float): a spatial split's piece (bvh_spatial.c). False when the triangle misses the box.
bool tri_clip_bounds(vec3 p0, vec3 p1, vec3 p2, const float lo[3], const float hi[3], bounds3 *out);

#endif
