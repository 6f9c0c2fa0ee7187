#include "compositor/kernels.hpp"

#include "shared_types.h"

namespace decalcomp {

namespace {

// The point shading kernels in DC_VARIANT_x bit order; ShadingPaths::key takes the two bits below
// DC_VARIANT_POINT for the variant.
static_assert(DC_VARIANT_ALBEDO_ONLY == 1 && DC_VARIANT_FLAT == 2 && DC_VARIANT_POINT == 4,
              "point_shade_ is indexed by the variant bits, and ShadingPaths::key keeps the lower two");

}  // namespace

CompositorKernels::CompositorKernels(const cl::Program& program)
    : tile_bounds(program, "dc_tile_bounds"),
      tile_bounds_serial(program, "dc_tile_bounds_serial"),
      decal_bounds(program, "dc_decal_bounds"),
      coarse_depth(program, "dc_coarse_depth"),
      coarse_mark(program, "dc_coarse_mark"),
      coarse_count(program, "dc_coarse_count"),
      coarse_count_serial(program, "dc_coarse_count_serial"),
      coarse_fill(program, "dc_coarse_fill"),
      bin_count(program, "dc_bin_count"),
      bin_count_serial(program, "dc_bin_count_serial"),
      bin_fill(program, "dc_bin_fill"),
      scan(program, "dc_scan"),
      occlusion_build(program, "dc_occlusion_build"),
      rest_lookup(program, "dc_rest_lookup"),
      rest_frame(program, "dc_rest_frame"),
      clean_depths(program, "dc_clean_depths"),
      point_shade_{Shade(program, "dc_shade_point"), Shade(program, "dc_shade_point_albedo"),
                   Shade(program, "dc_shade_point_flat"), Shade(program, "dc_shade_point_albedo_flat")} {}

CompositorKernels::Shade& CompositorKernels::shading(int variant, const ShadingPaths& paths, ComputeDevice& device) {
    if (variant & DC_VARIANT_POINT) return point_shade_.at(std::size_t(variant & ~DC_VARIANT_POINT));
    const int key = paths.key(variant);
    auto found = shade_.find(key);
    if (found == shade_.end())
        found = shade_.emplace(key, Shade(device.shadingProgram(variant, paths), "dc_shade")).first;
    return found->second;
}

}  // namespace decalcomp
