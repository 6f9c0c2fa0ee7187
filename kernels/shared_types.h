/* Plain structs shared by the host (C++) and the kernels (OpenCL C 1.2).
 * Only 4-byte scalars and arrays of them, so both compilers lay them out identically;
 * src/cl/shared_types_check.cpp static_asserts every size and offset. */
#ifndef DECALCOMP_SHARED_TYPES_H
#define DECALCOMP_SHARED_TYPES_H

/* __OPENCL_VERSION__ comes from the device's compiler, __OPENCL_C_VERSION__ from any OpenCL C
 * 1.2 compiler (clang's build-time check defines only the latter). */
#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define DC_OPENCL_C 1
#endif

#ifdef DC_OPENCL_C
#define DC_INT int
#define DC_FLOAT float
/* For the per-decal functions: compilers otherwise keep them out of line and pass their structs
 * through stack memory for every pixel-decal pair (NVIDIA: 3.7x slower unbinned shading at 1080p;
 * PoCL: texture lookups stalled on the copied DcTexture; docs/benchmarks.md). */
#define DC_INLINE __attribute__((always_inline)) inline
/* DC_CPU_DEVICE: the host builds for a CPU device (PoCL), whose work-items run one after another as
 * scalar code. A call there spills every live vector register, so the filtered path's per-pixel and
 * per-decal helpers are forced inline (PoCL: `:fast` about 5 % faster); GPU compilers inline them of
 * their own accord, and forcing the set-up's multiplied NVIDIA's build time (docs/benchmarks.md,
 * stop 53). */
#ifdef DC_CPU_DEVICE
#define DC_CPU_INLINE DC_INLINE
#else
#define DC_CPU_INLINE inline
#endif
#else
#include <cstdint>
#define DC_INT std::int32_t
#define DC_FLOAT float
namespace decalcomp::cl_types {
#endif

/* Depth conventions, see docs/conventions.md. */
#define DC_DEPTH_PLANAR 0
#define DC_DEPTH_RADIAL 1
#define DC_DEPTH_NDC 2
#define DC_DEPTH_POSITION 3

#define DC_KIND_BOX 0
#define DC_KIND_VOLUME 1
#define DC_KIND_FRUSTUM 2
#define DC_KIND_CUBE 3

/* Screen tiles are DC_TILE_SIZE square; the tile kernel runs one work-group per tile. */
#define DC_TILE_SIZE 16
/* Binning's first level works on coarse tiles of DC_COARSE_TILES x DC_COARSE_TILES tiles. */
#define DC_COARSE_TILES 4
/* The coarse binning marks decals in 64-bit mask words (ulong / cl_ulong), one bit per decal:
 * a frame's decals are split into (decal_count + DC_DECALS_PER_MASK_WORD - 1) /
 * DC_DECALS_PER_MASK_WORD chunks. */
#define DC_DECALS_PER_MASK_WORD 64
/* Work-items per decal that mark the coarse tiles it overlaps (dc_coarse_mark, binning.cl). */
#define DC_MARK_LANES 32
/* Work-group sizes of binning.cl's per-tile kernels: a coarse tile's chunks are prefix-summed
 * DC_CHUNK_LANES at a time (dc_coarse_count), and a tile's coarse list is tested DC_BIN_LANES
 * entries at a time (dc_bin_count). */
#define DC_CHUNK_LANES 64
#define DC_BIN_LANES 32
/* The prefix sums of tile counts run in one work-group of DC_SCAN_GROUP work-items (scan.cl). */
#define DC_SCAN_GROUP 256

#define DC_FILTER_NEAREST 0
#define DC_FILTER_LINEAR 1
#define DC_FILTER_MIP 2 /* trilinear over a mip chain, level from the pixel's footprint */

/* The renderer's pixel filter (pixel_filter.hpp): at most this many quadrature taps per axis. */
#define DC_MAX_FILTER_TAPS 8
/* Its edge-spread table (pixel_filter.hpp edgeSpreadTable): rows of normal ratios, steps of distance. */
#define DC_EDGE_SPREAD_RATIOS 9
#define DC_EDGE_SPREAD_STEPS 33

/* Material attributes a decal writes, in this order in DcDecal's per-target arrays. */
#define DC_TARGET_ALBEDO 0
#define DC_TARGET_NORMAL 1
#define DC_TARGET_ROUGHNESS 2
#define DC_TARGET_METALLIC 3
#define DC_TARGET_AO 4
#define DC_TARGET_EMISSION 5
#define DC_TARGETS 6
/* DcFrame::attributes: bit (1 << DC_TARGET_x) set when the frame has that plane. */

/* Blend ops for every target but the normal (docs/scene-format.md "Materials"). */
#define DC_OP_OVER 0
#define DC_OP_MULTIPLY 1
#define DC_OP_ADD 2
#define DC_OP_REPLACE 3

/* Shading-kernel variants (a literal in each kernel, so the compiler drops what a variant
 * excludes; the host picks the leanest that fits the scene). */
#define DC_VARIANT_ALBEDO_ONLY 1 /* no other target, no blast occlusion */
#define DC_VARIANT_FLAT 2        /* box and frustum decals only: no cube or volume lookups */
#define DC_VARIANT_POINT 4       /* point-sampled, no texture-space decal: no pixel filter or rest pose */

/* How a decal's normal map combines with the surface normal. */
#define DC_NORMAL_RNM 0 /* reoriented normal mapping */
#define DC_NORMAL_UDN 1
#define DC_NORMAL_WHITEOUT 2
#define DC_NORMAL_REPLACE 3 /* the map in the decal's own frame, ignoring the surface's detail */

/* Pixels with a planar view depth below this are never decaled (the binning clips decal
 * volumes at this distance in front of the camera). */
#define DC_MIN_VIEW_DEPTH 1e-6f
/* Depths at or beyond this are background, whatever the convention (Blender writes 1e10). */
#define DC_BACKGROUND_DEPTH 1e10f

/* One frame: camera and layout. Matrices are row-major, acting on column vectors. */
typedef struct {
    DC_FLOAT inv_projection[16]; /* clip -> camera space */
    DC_FLOAT projection[16];     /* camera space -> clip */
    DC_FLOAT world_to_camera[16];
    DC_INT width, height;               /* data window */
    DC_INT origin_x, origin_y;          /* data window min - display window min */
    DC_INT display_width, display_height;
    DC_INT depth_convention;
    DC_INT reversed_z;
    DC_FLOAT far_plane; /* planar depths beyond it are background; 0 = no limit */
    DC_INT orthographic;
    DC_INT tiles_x, tiles_y;
    DC_INT decal_count;
    DC_INT has_depth;  /* 0: position convention without a depth pass */
    DC_INT has_normal; /* a world-space normal image is bound (angle fades) */
    DC_INT reconstruct_normals; /* no normal pass but angle fades: normals from depth neighbours */
    DC_INT attributes; /* bits (1 << DC_TARGET_x): material planes the frame has and decals change */
    DC_INT needs_footprint; /* some decal filters with mips: compute the pixel footprint */
    /* The beauty update (beauty.h): off unless `beauty`; the light planes hold the albedo lobe's
     * terms, direct ones first, the first summed_terms adding up in the beauty. */
    DC_INT beauty;
    DC_INT light_terms, direct_terms, summed_terms;
    DC_INT light_divided;   /* 1: light divided by its colour (Blender); 0: multiplied by it */
    DC_INT beauty_emission; /* 1: emission changes add to the beauty */
    DC_INT relight;         /* 1: direct light scaled by the Lambert ratio of new and old normal */
    DC_INT rest_frames;     /* 1: the rest pass left each pixel's rest -> camera rotation (rest_pose.h) */
    DC_INT rest_decals;     /* 1: some decal is texture-space (its rest_binding >= 0) */
    DC_INT change_in_light; /* 1: the beauty's change overwrites the one light term (beauty_transfer.hpp) */
    DC_FLOAT light_fit[4]; /* direct light ~ max(0, [3] + dot([0..2], world normal)) */
    /* Decals integrated over the renderer's pixel filter (docs/pixel-filter.md): filter_taps per
     * axis (0: point-sampled at the pixel centre), at filter_offset pixels from the centre with
     * separable weights filter_weight, each prefiltering a stratum filter_step pixels wide. */
    DC_INT filter_taps;
    DC_FLOAT filter_step, filter_radius;
    DC_INT clean_plane; /* 1: dc_clean_depths filled the clean-depth plane; 0: scans test neighbours */
    DC_FLOAT filter_offset[DC_MAX_FILTER_TAPS];
    DC_FLOAT filter_weight[DC_MAX_FILTER_TAPS];
    /* Pixels on one tangent plane integrate each decal over the filter in closed form
     * (docs/pixel-filter.md "Integrated evaluation"): edges through the edge-spread table, texture
     * reads that cannot weight texels one by one over a box filter_box pixels wide. */
    DC_FLOAT filter_box;
    DC_INT filter_fast; /* 1: those pixels take the closed form; 0: the taps */
    DC_INT pad5, pad6;
    DC_FLOAT filter_edge[DC_EDGE_SPREAD_RATIOS * DC_EDGE_SPREAD_STEPS];
} DcFrame;

/* One decal, prepared on the host in double precision. */
typedef struct {
    DC_FLOAT camera_to_local[12]; /* rows 0..2 of inverse(M) * camera_to_world */
    DC_FLOAT local_to_camera[12]; /* rows 0..2 of world_to_camera * M */
    DC_INT kind;
    DC_INT filter;
    DC_INT texture; /* index into the texture table, -1 = none */
    DC_FLOAT opacity;
    DC_INT mask; /* index of the frame's mask weight plane, -1 = none */
    /* frustum: tan(fov_y / 2), aspect, near, far in local units */
    DC_FLOAT tan_half_fov_y, aspect, near_plane, far_plane;
    /* box/volume: camera-space unit vector of local +Z, the normal of surfaces facing the decal */
    DC_FLOAT facing_axis[3];
    /* angle fade in radians from the facing direction: full up to [0], none from [1]; off if [1] <= 0 */
    DC_FLOAT angle_fade[2];
    DC_FLOAT axis_fade;       /* box/volume: faded fraction of the half-depth at both z ends; 0 = off */
    DC_FLOAT distance_fade[2]; /* frustum: fade from distance [0] to [1]; off if [1] <= 0 */
    /* The rest of the texture set (albedo is `texture`): indices into the table, -1 = none. */
    DC_INT normal_texture, orm_texture, emission_texture;
    /* Per target (DC_TARGET_x): factor (0 = the decal leaves it alone) and blend op. */
    DC_FLOAT factor[DC_TARGETS];
    DC_INT op[DC_TARGETS];
    /* Constants used where the set has no texture for a target; value_mask bit per target. */
    DC_FLOAT albedo_value[3], emission_value[3];
    DC_FLOAT roughness_value, metallic_value, ao_value;
    DC_INT value_mask;
    DC_INT normal_blend;     /* DC_NORMAL_x */
    DC_FLOAT normal_strength; /* scales the map's tangent-plane tilt */
    /* blast occlusion (frustum, cube): first texel of the decal's map in the map buffer, -1 = off;
     * the map is occlusion_width x occlusion_height per face (1 face frustum, 6 cube) */
    DC_INT occlusion_map;
    DC_INT occlusion_width, occlusion_height;
    DC_FLOAT occlusion_bias; /* slope-scaled bias in texels */
    /* lengths of camera_to_local's rows: how far a camera-space distance moves each local axis */
    DC_FLOAT local_scale[3];
    /* texture-space decal (rest_pose.h): its DcRestBinding, -1 = a world decal. Then "camera space"
     * in the fields above is the rest mesh's object space. */
    DC_INT rest_binding;
    /* 1: a texture-space decal in bake mode (kernels/bake.cl): its textures are its UV-space bake,
     * looked up at the pixel's UV (the rest pass leaves UVs, not rest points, for its binding) */
    DC_INT rest_baked;
} DcDecal;

/* A texture-space binding (docs/texture-space.md): a rest mesh's UV grid and the mask of the object
 * its decals stick to. Mesh data: 3 float4 per vertex, (position, u), (normal, v), (tangent,
 * handedness); int4 triangles; the grid's cells list triangle indices (absolute). */
typedef struct {
    DC_FLOAT uv_origin[2];
    DC_FLOAT cells_per_uv[2];
    DC_INT cells_x, cells_y;
    DC_INT first_cell; /* the grid's cells_x * cells_y + 1 offsets (into the triangle list) start here */
    DC_INT mask;       /* weight plane of the object's pixels; -1: every pixel */
    DC_INT flip_v;     /* 1: the UV pass counts v from the top, the mesh from the bottom */
    DC_INT uv_only;    /* 1: bake mode: the rest pass leaves (u, v) per object pixel, no triangle search */
    DC_INT pad1, pad2;
} DcRestBinding;

/* One UV-space bake (kernels/bake.cl): a width x height layer, row 0 at v = 1 (the top of the
 * image, as DCCs show UV layouts); texels within `dilation` texels of an island get values from
 * across its border (docs/texture-space.md "Bake mode"). Grids: the rest mesh's and its apron's. */
typedef struct {
    DC_INT width, height;
    DC_INT dilation;
    DC_INT pad0;
} DcBakeLayer;

/* Where a texture's texels (float4, premultiplied linear RGBA, top row first) start. */
typedef struct {
    DC_INT offset;
    DC_INT width, height;
    DC_INT depth;  /* slices: 1 for 2D, D for a volume, 6 for a cube */
    DC_INT levels; /* mip levels from this one down; level l is the table entry l places later */
    DC_INT pad0, pad1, pad2;
} DcTexture;

/* A decal's conservative screen footprint: inclusive tile range and planar depth range, and the
 * inclusive pixel range within the frame that the shading kernel tests before a decal's transform. */
typedef struct {
    DC_INT tile_x0, tile_y0, tile_x1, tile_y1; /* empty when x0 > x1 */
    DC_FLOAT depth_min, depth_max;
    DC_INT pixel_x0, pixel_y0, pixel_x1, pixel_y1;
} DcDecalBounds;

#ifndef DC_OPENCL_C
}  // namespace decalcomp::cl_types
#endif

#endif
