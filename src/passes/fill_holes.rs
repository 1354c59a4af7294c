//! The G-buffer-guided warp's hole fill, as a pass of its own over the holes the warp listed
//! (`shaders/fill_holes.wgsl`): one invocation per hole, dispatched indirectly from the warp's
//! count. In the warp itself the fill's 81 taps cost every pixel on lavapipe, hole or not.

use crate::passes::warp::{bind_common, storing, HoleList, Params, Store, WarpInputs};
use crate::passes::{CounterRange, Texture};
use crate::shaders::fill_holes::binding;
use crate::vk::recorder::Recorder;

/// Records the fill of the holes `holes` lists into `warped`, after the warp that listed them
/// and with its parameters, storing as it did.
pub fn record(
    rec: &mut Recorder,
    params: &Params,
    inputs: &WarpInputs,
    store: Store,
    warped: Texture,
    counters: &CounterRange,
    holes: &HoleList,
) {
    let bound = rec.bind(holes.fill, |writes| {
        bind_common(writes, inputs, store, warped, counters)
            .image(binding::HOLE_LIST, holes.list)
            .buffer(binding::DEFERRED, holes.deferred)
    });
    // `DeferredHoles.count`, then `groups` and the two ones after it.
    let part = |offset, range| CounterRange {
        buffer: holes.deferred.buffer,
        offset: holes.deferred.offset + offset,
        range,
    };
    let capacity = params.extent[0] as u64 * params.extent[1] as u64;
    rec.dispatch_listed(
        &bound,
        &storing(params, inputs, store),
        &part(4, 12),
        &part(0, 4),
        capacity,
    );
}
