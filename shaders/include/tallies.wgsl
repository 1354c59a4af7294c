// Counting in two steps: each invocation adds to its workgroup's tallies, then one lane adds each
// tally to the frame's counter, so that a frame costs at most one global atomic per workgroup and
// counter rather than one per pixel. A pass calls `open_tallies(lane)` before its pixel work and
// hands the tallies on where `close_tallies(lane)` is true after it. Both hold barriers, so both
// are called in uniform control flow. Tallies are indexed by constants: naga has no bounds check
// for a computed index into atomics.

var<workgroup> group_tallies: array<atomic<u32>, 5>;

fn open_tallies(lane: u32) {
    if (lane == 0u) {
        atomicStore(&group_tallies[0], 0u);
        atomicStore(&group_tallies[1], 0u);
        atomicStore(&group_tallies[2], 0u);
        atomicStore(&group_tallies[3], 0u);
        atomicStore(&group_tallies[4], 0u);
    }
    workgroupBarrier();
}

// True in the one lane that hands the tallies on, once every invocation has counted, where the
// workgroup counted anything: every workgroup of a frame adds to the same few counters, and on a
// GPU atomics on one address take turns, so a workgroup with nothing to add adds nothing.
fn close_tallies(lane: u32) -> bool {
    workgroupBarrier();
    let any = atomicLoad(&group_tallies[0]) | atomicLoad(&group_tallies[1])
        | atomicLoad(&group_tallies[2]) | atomicLoad(&group_tallies[3])
        | atomicLoad(&group_tallies[4]);
    return lane == 0u && any != 0u;
}
