//! The naga settings every shader is compiled with: the hand-written passes by build.rs (which
//! includes this file) and the generated network layers at run time.

use naga::back::spv;
use naga::valid::{Capabilities, ValidationFlags, Validator};

pub fn validator() -> Validator {
    // `quantizeToF16` and the half-float packing, which naga gates for targets that lack them,
    // are core SPIR-V for Vulkan (OpQuantizeToF16, GLSL.std.450's PackHalf2x16).
    Validator::new(
        ValidationFlags::all(),
        Capabilities::IMMEDIATES | Capabilities::SHADER_FLOAT16_IN_FLOAT32,
    )
}

pub fn spirv_options() -> spv::Options<'static> {
    // A frame generator must never read outside an engine image or a buffer: every image
    // coordinate and index is clamped into range. Clamping rather than reading zero keeps each
    // load unconditional, so a GPU issues a pass's loads together instead of one branch at a
    // time. (Stores are not checked by naga; the passes store only inside their extent.)
    let clamped = naga::proc::BoundsCheckPolicy::Restrict;
    let mut options = spv::Options {
        // Lavapipe lacks storageInputOutput16; compute passes never need it.
        use_storage_input_output_16: false,
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: clamped,
            buffer: clamped,
            image_load: clamped,
            binding_array: clamped,
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
