// The entry point of the three backward warps (warp.wgsl): each defines
// `warp_pixel(p, t, motion_vector)`, for target pixel p, its surface and its motion vector.

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);

    let p = id.xy;
    if (all(p < params.extent)) {
        // Each of the target's inputs is read once, here.
        let motion_vector = motion_at(p);
        let t = target_surface(p);
        let result = warp_pixel(p, t, motion_vector);
        if (!result.deferred) {
            store_pixel(p, result.fetched, result.hole);
        }
        if (!t.valid || !is_finite(vec4f(motion_vector, 0.0, 0.0))) {
            atomicAdd(&group_tallies[TALLY_INVALID_GEOMETRY], 1u);
        }
        if (result.hole) {
            atomicAdd(&group_tallies[TALLY_HOLES], 1u);
        }
        if (result.offscreen) {
            atomicAdd(&group_tallies[TALLY_OFFSCREEN], 1u);
        }
        // NaN and infinite vectors fail the comparison and are left out; the length is spelled
        // out so that vectors whose square overflows are left out on every driver alike.
        let scaled = motion_vector * params.motion_scale;
        let reach = sqrt(dot(scaled, scaled));
        // Only a reach beyond the workgroup's largest so far needs the atomic.
        let largest = atomicLoad(&group_tallies[TALLY_LARGEST_MOTION]);
        if (reach <= MAX_FINITE && bitcast<u32>(reach) > largest) {
            atomicMax(&group_tallies[TALLY_LARGEST_MOTION], bitcast<u32>(reach));
        }
    }

    // Each counter only where the workgroup has something to add to it (`close_tallies`): every
    // workgroup counts a largest motion, few a hole.
    if (close_tallies(lane)) {
        let holes = atomicLoad(&group_tallies[TALLY_HOLES]);
        if (holes != 0u) {
            atomicAdd(&counters.hole_pixels, holes);
        }
        let offscreen = atomicLoad(&group_tallies[TALLY_OFFSCREEN]);
        if (offscreen != 0u) {
            atomicAdd(&counters.offscreen_pixels, offscreen);
        }
        let largest = atomicLoad(&group_tallies[TALLY_LARGEST_MOTION]);
        if (largest > atomicLoad(&counters.largest_motion_bits)) {
            atomicMax(&counters.largest_motion_bits, largest);
        }
        let invalid = atomicLoad(&group_tallies[TALLY_INVALID_GEOMETRY]);
        if (invalid != 0u) {
            atomicAdd(&counters.invalid_geometry_pixels, invalid);
        }
        let sanitized = atomicLoad(&group_tallies[TALLY_SANITIZED]);
        if (sanitized != 0u) {
            atomicAdd(&counters.sanitized_pixels, sanitized);
        }
    }
}
