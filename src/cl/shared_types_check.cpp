// The structs in kernels/shared_types.h must have the same layout in C++ and OpenCL C:
// only 4-byte members, no padding, sizes fixed here.
#include <cstddef>

#include "shared_types.h"

namespace decalcomp::cl_types {

static_assert(sizeof(DcFrame) == 272, "DcFrame layout changed: update the kernels too");
static_assert(offsetof(DcFrame, attributes) == 256);
static_assert(offsetof(DcFrame, projection) == 64);
static_assert(offsetof(DcFrame, world_to_camera) == 128);
static_assert(offsetof(DcFrame, width) == 192);
static_assert(offsetof(DcFrame, far_plane) == 224);
static_assert(offsetof(DcFrame, has_depth) == 244);
static_assert(offsetof(DcFrame, has_normal) == 248);
static_assert(offsetof(DcFrame, reconstruct_normals) == 252);
static_assert(sizeof(DcDecal) == 288);
static_assert(offsetof(DcDecal, normal_texture) == 164);
static_assert(offsetof(DcDecal, factor) == 176);
static_assert(offsetof(DcDecal, op) == 200);
static_assert(offsetof(DcDecal, value_mask) == 260);
static_assert(offsetof(DcDecal, occlusion_map) == 272);
static_assert(offsetof(DcDecal, occlusion_bias) == 284);
static_assert(offsetof(DcDecal, facing_axis) == 132);
static_assert(offsetof(DcDecal, distance_fade) == 156);
static_assert(offsetof(DcDecal, mask) == 112);
static_assert(offsetof(DcDecal, local_to_camera) == 48);
static_assert(offsetof(DcDecal, kind) == 96);
static_assert(offsetof(DcDecal, opacity) == 108);
static_assert(sizeof(DcTexture) == 32);
static_assert(sizeof(DcDecalBounds) == 32);
static_assert(offsetof(DcDecalBounds, depth_min) == 16);

}  // namespace decalcomp::cl_types
