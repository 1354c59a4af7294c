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

// After the three patches: the indirect dispatch of each step of the two networks run side by
// side (the gather, then each layer), which covers both networks' workgroups at that step: the
// first network's rows, then the second's below them, as wide as the wider.
struct PatchSlots {
    patches: array<PatchSlot, 3>,
    steps: array<vec4u, 16>,
}

// Which network a step's workgroup `group` works for (the second where `second`, whose rows
// follow the first network's dispatch `first`), and which workgroup of that network's own
// dispatch it is.
struct StepGroup {
    group: vec2u,
    second: bool,
}

fn step_group(group: vec2u, first: vec4u) -> StepGroup {
    let second = group.y >= first.y;
    return StepGroup(vec2u(group.x, select(group.y, group.y - first.y, second)), second);
}
