#include "compositor/kernels.hpp"

#include "shared_types.h"

namespace decalcomp {

namespace {

// The shading kernels in DC_VARIANT_x bit order.
static_assert(DC_VARIANT_ALBEDO_ONLY == 1 && DC_VARIANT_FLAT == 2 && DC_VARIANT_POINT == 4,
              "shade_ is indexed by the variant bits");

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
      shade_{std::nullopt,
             std::nullopt,
             std::nullopt,
             std::nullopt,
             Shade(program, "dc_shade_point"),
             Shade(program, "dc_shade_point_albedo"),
             Shade(program, "dc_shade_point_flat"),
             Shade(program, "dc_shade_point_albedo_flat")} {}

CompositorKernels::Shade& CompositorKernels::shading(int variant, const std::function<const cl::Program&()>& full) {
    std::optional<Shade>& kernel = shade_.at(std::size_t(variant));
    if (!kernel) {
        static const char* const names[4] = {"dc_shade", "dc_shade_albedo", "dc_shade_flat", "dc_shade_albedo_flat"};
        kernel.emplace(full(), names[variant]);  // (the point variants are all built above)
    }
    return *kernel;
}

}  // namespace decalcomp
