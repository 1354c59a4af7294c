// Plans where the two inpainting networks run, from the objects' totals that object_bounds
// left: the FI patch bounds every dynamic object's pixels, the near-BE patch every grown
// rectangle (`grown_rect`), which it lists as grow_regions would, in its place.
// Each is widened by a margin of context, clamped to the frame, rounded up to its network's
// multiple (patch texels past the frame read as zero), and given the indirect dispatch of each
// of its network's levels. With a resolution divisor d a network texel covers d x d pixels, so
// the patch's extent in texels is a d-th of its extent in the frame. A patch that would span
// more texels than the tensors hold (`max_patch_side`, or the frame's own extent if smaller)
// doubles its divisor until it fits. The blend patch bounds both, for the pass that scatters
// the results back. A frame without dynamic objects, or a network that is off (levels 0), gets
// an empty patch that dispatches no workgroup. With `whole_frame` (the ablation of foveated
// segmentation) the FI patch is the whole frame instead. Each step of the two networks run
// side by side gets the dispatch that covers both networks' workgroups (`step_group`).
// src/reference/inpaint.rs mirrors the patches.
// #import segmentation
// #import patch

struct Params {
    extent: vec2u,
    margin: u32,
    group_edge: u32,
    // Levels of the FI and the near-BE network; 0 for a network that does not run.
    levels: vec2u,
    whole_frame: u32,
    divisor: u32,
    max_patch_side: u32,
    // k_x and k_y of Algorithm 1.
    growth: vec2f,
    // Per network (two words each, FI's first), four bits per step: the level its pass at that
    // step runs at, plus one; 0 where it has no pass (`NetworkPipelines::step_table`).
    step_levels: vec4u,
}
var<immediate> params: Params;

@group(0) @binding(0) var<storage, read> totals: ObjectTable;
@group(0) @binding(1) var<storage, read_write> slots: PatchSlots;
@group(0) @binding(2) var<storage, read_write> list: RectTable;

const EMPTY: u32 = 0xffffffffu;

// A rectangle [lo, hi) of the frame; empty unless lo < hi on both axes.
struct Span {
    lo: vec2u,
    hi: vec2u,
}

fn union_span(a: Span, b: Span) -> Span {
    if (any(b.lo >= b.hi)) {
        return a;
    }
    return Span(min(a.lo, b.lo), max(a.hi, b.hi));
}

// The frame pixels a network's patch covers, [lo, hi), and how many each texel covers a side.
struct Planned {
    span: Span,
    divisor: u32,
}

// Network texels over `pixels` frame pixels at divisor `d`, rounded up to the network's multiple.
fn texels_at(pixels: vec2u, d: u32, multiple: u32) -> vec2u {
    return ((pixels + vec2u(d - 1u)) / d + vec2u(multiple - 1u)) / multiple * multiple;
}

// The patch of a network with `levels` levels over `span`.
fn plan(span: Span, levels: u32) -> Planned {
    if (levels == 0u || any(span.lo >= span.hi)) {
        return Planned(Span(vec2u(0u), vec2u(0u)), params.divisor);
    }
    let origin = span.lo - min(span.lo, vec2u(params.margin));
    let end = min(span.hi + vec2u(params.margin), params.extent);
    let multiple = 1u << (levels - 1u);
    let capacity = texels_at(min(params.extent, vec2u(params.max_patch_side)), 1u, multiple);
    var d = params.divisor;
    var texels = texels_at(end - origin, d, multiple);
    // It fits by the time d spans the frame (one multiple of texels); the bound only guards
    // the loop.
    for (var doubled = 0u; doubled < 16u && any(texels > capacity); doubled++) {
        d *= 2u;
        texels = texels_at(end - origin, d, multiple);
    }
    return Planned(Span(origin, origin + texels * d), d);
}

// The level network `network`'s pass at step `step` runs at, plus one; 0 where it has none.
fn step_code(network: u32, step: u32) -> u32 {
    return (params.step_levels[2u * network + step / 8u] >> (4u * (step % 8u))) & 0xfu;
}

// Each step's dispatch: the first network's rows of workgroups, the second's below them.
fn write_steps() {
    for (var step = 0u; step < 16u; step++) {
        var groups = vec2u(0u);
        for (var network = 0u; network < 2u; network++) {
            let code = step_code(network, step);
            if (code != 0u) {
                let own = slots.patches[network].value.dispatch[code - 1u].xy;
                groups = vec2u(max(groups.x, own.x), groups.y + own.y);
            }
        }
        slots.steps[step] = vec4u(groups, 1u, 0u);
    }
}

fn write_patch(slot: u32, planned: Planned, levels: u32) {
    let extent = (planned.span.hi - planned.span.lo) / planned.divisor;
    slots.patches[slot].value.origin = planned.span.lo;
    slots.patches[slot].value.extent = extent;
    slots.patches[slot].value.divisor = planned.divisor;
    for (var level = 0u; level < 6u; level++) {
        var groups = vec2u(0u);
        if (level < levels) {
            groups = ((extent >> vec2u(level)) + vec2u(params.group_edge - 1u)) / params.group_edge;
        }
        slots.patches[slot].value.dispatch[level] = vec4u(groups, 1u, 0u);
    }
}

@compute @workgroup_size(1, 1, 1)
fn main() {
    let nothing = Span(vec2u(EMPTY), vec2u(0u));
    var fi = nothing;
    var near_be = nothing;
    var rects = 0u;
    for (var object = 1u; object < MAX_OBJECTS; object++) {
        let o = totals.objects[object];
        if (o.pixels == 0u) {
            continue;
        }
        let lo = vec2u(EMPTY - o.min_flipped[0], EMPTY - o.min_flipped[1]);
        let hi = vec2u(o.max[0], o.max[1]) + vec2u(1u);
        fi = union_span(fi, Span(lo, hi));
        let rect = grown_rect(object, o, params.growth, params.extent);
        list.rects[rects] = rect;
        rects++;
        near_be = union_span(near_be, Span(vec2u(rect.left, rect.top), vec2u(rect.right, rect.bottom)));
    }
    list.rect_count = rects;
    if (params.whole_frame != 0u) {
        fi = Span(vec2u(0u), params.extent);
    }
    let fi_planned = plan(fi, params.levels.x);
    let near_be_planned = plan(near_be, params.levels.y);
    write_patch(PATCH_FI, fi_planned, params.levels.x);
    write_patch(PATCH_NEAR_BE, near_be_planned, params.levels.y);
    // The blend is one dispatch at the frame's resolution over what either network wrote.
    var blend = union_span(union_span(nothing, fi_planned.span), near_be_planned.span);
    blend.hi = min(blend.hi, params.extent);
    blend.lo = min(blend.lo, blend.hi);
    write_patch(PATCH_BLEND, Planned(blend, 1u), 1u);
    write_steps();
}
