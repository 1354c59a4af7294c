//! The naga settings every shader is compiled with: the hand-written passes by build.rs (which
//! includes this file) and the generated network layers at run time.

use naga::back::spv;
use naga::valid::{Capabilities, ValidationFlags, Validator};

pub fn validator() -> Validator {
    Validator::new(ValidationFlags::all(), Capabilities::IMMEDIATES)
}

pub fn spirv_options() -> spv::Options<'static> {
    // A frame generator must never read or write outside an engine image. Buffer indices are
    // clamped instead, the one policy naga implements for atomics.
    let checked = naga::proc::BoundsCheckPolicy::ReadZeroSkipWrite;
    let mut options = spv::Options {
        // Lavapipe lacks storageInputOutput16; compute passes never need it.
        use_storage_input_output_16: false,
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: checked,
            buffer: naga::proc::BoundsCheckPolicy::Restrict,
            image_load: checked,
            binding_array: checked,
        },
        // Every shader writes its workgroup memory before reading it (`open_tallies`, the flow's
        // strips). naga's zero-fill would cost each workgroup one more barrier, and a barrier is
        // a coroutine switch per invocation on lavapipe.
        zero_initialize_workgroup_memory: spv::ZeroInitializeWorkgroupMemoryMode::None,
        ..Default::default()
    };
    options.flags.remove(spv::WriterFlags::DEBUG);
    options
}
