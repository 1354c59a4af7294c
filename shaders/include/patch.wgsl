// Where a network runs: the origin of its patch in the frame, its padded extent in network
// texels and how many frame pixels a texel covers per axis (its resolution divisor), then the
// indirect dispatch of each level's layers (src/network/codegen.rs, src/passes/inpaint.rs).
struct Patch {
    origin: vec2u,
    extent: vec2u,
    divisor: u32,
    // x, y, z workgroups of each level's dispatch, and one unused word.
    dispatch: array<vec4u, 6>,
}

// An extrapolation's patches (plan_patches, blend_patches), each on its own 256-byte boundary,
// the largest storage-buffer offset alignment, so that a network's passes can bind one alone.
struct PatchSlot {
    value: Patch,
    unused: array<vec4u, 8>,
}
const PATCH_FI: u32 = 0u;
const PATCH_NEAR_BE: u32 = 1u;
const PATCH_BLEND: u32 = 2u;
