// The structs in kernels/shared_types.h must have the same layout in C++ and OpenCL C (only
// 4-byte members, no padding), and every host enum the values of its DC_* codes. This file is
// compiled as C++ into the library and as OpenCL C by the build-time kernel check
// (CMakeLists.txt, clang -x cl), so the offsets below hold for both compilers.
#include "shared_types.h"

#ifdef DC_OPENCL_C
#define DC_CHECK(condition) _Static_assert(condition, #condition)
#define DC_OFFSET(type, member) __builtin_offsetof(type, member)
#else
#include <CL/cl_platform.h>

#include <cstddef>

#include "decalcomp/decal.hpp"
#include "decalcomp/gbuffer.hpp"
#include "decalcomp/pixel_filter.hpp"
#define DC_CHECK(condition) static_assert(condition, #condition)
#define DC_OFFSET(type, member) offsetof(type, member)
namespace decalcomp::cl_types {
#endif

DC_CHECK(sizeof(DC_INT) == 4 && sizeof(DC_FLOAT) == 4);

DC_CHECK(sizeof(DcFrame) == 1604);
DC_CHECK(DC_OFFSET(DcFrame, inv_projection) == 0);
DC_CHECK(DC_OFFSET(DcFrame, projection) == 64);
DC_CHECK(DC_OFFSET(DcFrame, world_to_camera) == 128);
DC_CHECK(DC_OFFSET(DcFrame, width) == 192);
DC_CHECK(DC_OFFSET(DcFrame, height) == 196);
DC_CHECK(DC_OFFSET(DcFrame, origin_x) == 200);
DC_CHECK(DC_OFFSET(DcFrame, origin_y) == 204);
DC_CHECK(DC_OFFSET(DcFrame, display_width) == 208);
DC_CHECK(DC_OFFSET(DcFrame, display_height) == 212);
DC_CHECK(DC_OFFSET(DcFrame, depth_convention) == 216);
DC_CHECK(DC_OFFSET(DcFrame, reversed_z) == 220);
DC_CHECK(DC_OFFSET(DcFrame, far_plane) == 224);
DC_CHECK(DC_OFFSET(DcFrame, orthographic) == 228);
DC_CHECK(DC_OFFSET(DcFrame, tiles_x) == 232);
DC_CHECK(DC_OFFSET(DcFrame, tiles_y) == 236);
DC_CHECK(DC_OFFSET(DcFrame, decal_count) == 240);
DC_CHECK(DC_OFFSET(DcFrame, has_depth) == 244);
DC_CHECK(DC_OFFSET(DcFrame, has_normal) == 248);
DC_CHECK(DC_OFFSET(DcFrame, reconstruct_normals) == 252);
DC_CHECK(DC_OFFSET(DcFrame, attributes) == 256);
DC_CHECK(DC_OFFSET(DcFrame, needs_footprint) == 260);
DC_CHECK(DC_OFFSET(DcFrame, beauty) == 264);
DC_CHECK(DC_OFFSET(DcFrame, light_terms) == 268);
DC_CHECK(DC_OFFSET(DcFrame, direct_terms) == 272);
DC_CHECK(DC_OFFSET(DcFrame, summed_terms) == 276);
DC_CHECK(DC_OFFSET(DcFrame, light_divided) == 280);
DC_CHECK(DC_OFFSET(DcFrame, beauty_emission) == 284);
DC_CHECK(DC_OFFSET(DcFrame, relight) == 288);
DC_CHECK(DC_OFFSET(DcFrame, rest_frames) == 292);
DC_CHECK(DC_OFFSET(DcFrame, rest_decals) == 296);
DC_CHECK(DC_OFFSET(DcFrame, change_in_light) == 300);
DC_CHECK(DC_OFFSET(DcFrame, light_fit) == 304);
DC_CHECK(DC_OFFSET(DcFrame, filter_taps) == 320);
DC_CHECK(DC_OFFSET(DcFrame, filter_step) == 324);
DC_CHECK(DC_OFFSET(DcFrame, filter_radius) == 328);
DC_CHECK(DC_OFFSET(DcFrame, clean_plane) == 332);
DC_CHECK(DC_OFFSET(DcFrame, filter_offset) == 336);
DC_CHECK(DC_OFFSET(DcFrame, filter_weight) == 368);
DC_CHECK(DC_OFFSET(DcFrame, filter_box) == 400);
DC_CHECK(DC_OFFSET(DcFrame, filter_fast) == 404);
DC_CHECK(DC_OFFSET(DcFrame, filter_edge) == 416);

DC_CHECK(sizeof(DcDecal) == 308);
DC_CHECK(DC_OFFSET(DcDecal, camera_to_local) == 0);
DC_CHECK(DC_OFFSET(DcDecal, local_to_camera) == 48);
DC_CHECK(DC_OFFSET(DcDecal, kind) == 96);
DC_CHECK(DC_OFFSET(DcDecal, filter) == 100);
DC_CHECK(DC_OFFSET(DcDecal, texture) == 104);
DC_CHECK(DC_OFFSET(DcDecal, opacity) == 108);
DC_CHECK(DC_OFFSET(DcDecal, mask) == 112);
DC_CHECK(DC_OFFSET(DcDecal, tan_half_fov_y) == 116);
DC_CHECK(DC_OFFSET(DcDecal, aspect) == 120);
DC_CHECK(DC_OFFSET(DcDecal, near_plane) == 124);
DC_CHECK(DC_OFFSET(DcDecal, far_plane) == 128);
DC_CHECK(DC_OFFSET(DcDecal, facing_axis) == 132);
DC_CHECK(DC_OFFSET(DcDecal, angle_fade) == 144);
DC_CHECK(DC_OFFSET(DcDecal, axis_fade) == 152);
DC_CHECK(DC_OFFSET(DcDecal, distance_fade) == 156);
DC_CHECK(DC_OFFSET(DcDecal, normal_texture) == 164);
DC_CHECK(DC_OFFSET(DcDecal, orm_texture) == 168);
DC_CHECK(DC_OFFSET(DcDecal, emission_texture) == 172);
DC_CHECK(DC_OFFSET(DcDecal, factor) == 176);
DC_CHECK(DC_OFFSET(DcDecal, op) == 200);
DC_CHECK(DC_OFFSET(DcDecal, albedo_value) == 224);
DC_CHECK(DC_OFFSET(DcDecal, emission_value) == 236);
DC_CHECK(DC_OFFSET(DcDecal, roughness_value) == 248);
DC_CHECK(DC_OFFSET(DcDecal, metallic_value) == 252);
DC_CHECK(DC_OFFSET(DcDecal, ao_value) == 256);
DC_CHECK(DC_OFFSET(DcDecal, value_mask) == 260);
DC_CHECK(DC_OFFSET(DcDecal, normal_blend) == 264);
DC_CHECK(DC_OFFSET(DcDecal, normal_strength) == 268);
DC_CHECK(DC_OFFSET(DcDecal, occlusion_map) == 272);
DC_CHECK(DC_OFFSET(DcDecal, occlusion_width) == 276);
DC_CHECK(DC_OFFSET(DcDecal, occlusion_height) == 280);
DC_CHECK(DC_OFFSET(DcDecal, occlusion_bias) == 284);
DC_CHECK(DC_OFFSET(DcDecal, local_scale) == 288);
DC_CHECK(DC_OFFSET(DcDecal, rest_binding) == 300);
DC_CHECK(DC_OFFSET(DcDecal, rest_baked) == 304);

DC_CHECK(sizeof(DcRestBinding) == 48);
DC_CHECK(DC_OFFSET(DcRestBinding, uv_origin) == 0);
DC_CHECK(DC_OFFSET(DcRestBinding, cells_per_uv) == 8);
DC_CHECK(DC_OFFSET(DcRestBinding, cells_x) == 16);
DC_CHECK(DC_OFFSET(DcRestBinding, cells_y) == 20);
DC_CHECK(DC_OFFSET(DcRestBinding, first_cell) == 24);
DC_CHECK(DC_OFFSET(DcRestBinding, mask) == 28);
DC_CHECK(DC_OFFSET(DcRestBinding, flip_v) == 32);
DC_CHECK(DC_OFFSET(DcRestBinding, uv_only) == 36);

DC_CHECK(sizeof(DcBakeLayer) == 16);
DC_CHECK(DC_OFFSET(DcBakeLayer, width) == 0);
DC_CHECK(DC_OFFSET(DcBakeLayer, height) == 4);
DC_CHECK(DC_OFFSET(DcBakeLayer, dilation) == 8);

DC_CHECK(sizeof(DcTexture) == 32);
DC_CHECK(DC_OFFSET(DcTexture, offset) == 0);
DC_CHECK(DC_OFFSET(DcTexture, width) == 4);
DC_CHECK(DC_OFFSET(DcTexture, height) == 8);
DC_CHECK(DC_OFFSET(DcTexture, depth) == 12);
DC_CHECK(DC_OFFSET(DcTexture, levels) == 16);
DC_CHECK(DC_OFFSET(DcTexture, pad0) == 20);
DC_CHECK(DC_OFFSET(DcTexture, pad1) == 24);
DC_CHECK(DC_OFFSET(DcTexture, pad2) == 28);

DC_CHECK(sizeof(DcDecalBounds) == 40);
DC_CHECK(DC_OFFSET(DcDecalBounds, tile_x0) == 0);
DC_CHECK(DC_OFFSET(DcDecalBounds, tile_y0) == 4);
DC_CHECK(DC_OFFSET(DcDecalBounds, tile_x1) == 8);
DC_CHECK(DC_OFFSET(DcDecalBounds, tile_y1) == 12);
DC_CHECK(DC_OFFSET(DcDecalBounds, depth_min) == 16);
DC_CHECK(DC_OFFSET(DcDecalBounds, depth_max) == 20);
DC_CHECK(DC_OFFSET(DcDecalBounds, pixel_x0) == 24);
DC_CHECK(DC_OFFSET(DcDecalBounds, pixel_y0) == 28);
DC_CHECK(DC_OFFSET(DcDecalBounds, pixel_x1) == 32);
DC_CHECK(DC_OFFSET(DcDecalBounds, pixel_y1) == 36);

#ifndef DC_OPENCL_C
}  // namespace decalcomp::cl_types

namespace decalcomp {

// The coarse binning's mask words are cl_ulong on the host and ulong in the kernels.
DC_CHECK(DC_DECALS_PER_MASK_WORD == 8 * sizeof(cl_ulong));

DC_CHECK(int(DepthConvention::Planar) == DC_DEPTH_PLANAR);
DC_CHECK(int(DepthConvention::Radial) == DC_DEPTH_RADIAL);
DC_CHECK(int(DepthConvention::Ndc) == DC_DEPTH_NDC);
DC_CHECK(int(DepthConvention::Position) == DC_DEPTH_POSITION);

DC_CHECK(int(DecalKind::Box) == DC_KIND_BOX);
DC_CHECK(int(DecalKind::Volume) == DC_KIND_VOLUME);
DC_CHECK(int(DecalKind::Frustum) == DC_KIND_FRUSTUM);
DC_CHECK(int(DecalKind::Cube) == DC_KIND_CUBE);

DC_CHECK(int(TextureFilter::Nearest) == DC_FILTER_NEAREST);
DC_CHECK(int(TextureFilter::Linear) == DC_FILTER_LINEAR);
DC_CHECK(int(TextureFilter::Mip) == DC_FILTER_MIP);

DC_CHECK(kMaxFilterTaps == DC_MAX_FILTER_TAPS);
DC_CHECK(kEdgeSpreadRatios == DC_EDGE_SPREAD_RATIOS && kEdgeSpreadSteps == DC_EDGE_SPREAD_STEPS);

DC_CHECK(int(DecalTarget::Albedo) == DC_TARGET_ALBEDO);
DC_CHECK(int(DecalTarget::Normal) == DC_TARGET_NORMAL);
DC_CHECK(int(DecalTarget::Roughness) == DC_TARGET_ROUGHNESS);
DC_CHECK(int(DecalTarget::Metallic) == DC_TARGET_METALLIC);
DC_CHECK(int(DecalTarget::AmbientOcclusion) == DC_TARGET_AO);
DC_CHECK(int(DecalTarget::Emission) == DC_TARGET_EMISSION);
DC_CHECK(kDecalTargets == DC_TARGETS);
DC_CHECK(sizeof(cl_types::DcDecal::factor) == DC_TARGETS * sizeof(float));
DC_CHECK(sizeof(cl_types::DcDecal::op) == DC_TARGETS * sizeof(std::int32_t));

DC_CHECK(int(BlendOp::Over) == DC_OP_OVER);
DC_CHECK(int(BlendOp::Multiply) == DC_OP_MULTIPLY);
DC_CHECK(int(BlendOp::Add) == DC_OP_ADD);
DC_CHECK(int(BlendOp::Replace) == DC_OP_REPLACE);

DC_CHECK(int(NormalBlend::Reoriented) == DC_NORMAL_RNM);
DC_CHECK(int(NormalBlend::Udn) == DC_NORMAL_UDN);
DC_CHECK(int(NormalBlend::Whiteout) == DC_NORMAL_WHITEOUT);
DC_CHECK(int(NormalBlend::Replace) == DC_NORMAL_REPLACE);

}  // namespace decalcomp
#endif
