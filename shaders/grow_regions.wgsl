// Segmentation, step 2 of 3 (Algorithm 1 of PatchEX): one invocation per object id. An object
// with pixels gets its grown rectangle (`grown_rect`) appended to the list of rectangles.
// #import segmentation

struct Params {
    extent: vec2u,
    growth: vec2f,
}
var<immediate> params: Params;

@group(0) @binding(0) var<storage, read> totals: ObjectTable;
@group(0) @binding(1) var<storage, read_write> list: RectList;

@compute @workgroup_size(64, 1, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let object = id.x;
    if (object == 0u || object >= MAX_OBJECTS || totals.objects[object].pixels == 0u) {
        return;
    }
    let slot = atomicAdd(&list.rect_count, 1u);
    list.rects[slot] = grown_rect(object, totals.objects[object], params.growth, params.extent);
}
