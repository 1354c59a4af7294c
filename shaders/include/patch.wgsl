// Where a network runs: the origin and the padded extent of its patch in the frame, then the
// indirect dispatch of each level's layers (src/network/codegen.rs, src/passes/inpaint.rs).
struct Patch {
    origin: vec2u,
    extent: vec2u,
    // x, y, z workgroups of each level's dispatch, and one unused word.
    dispatch: array<vec4u, 6>,
}
