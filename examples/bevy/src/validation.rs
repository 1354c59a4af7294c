//! Counts the Vulkan validation layer's messages. With `InstanceFlags::VALIDATION | DEBUG` wgpu
//! turns on the Khronos layer, with synchronization validation, and logs each warning and error
//! it reports under `wgpu_hal::vulkan`; this layer of Bevy's log keeps their text. wgpu runs
//! without the Khronos layer when it is not installed, saying so only at debug level:
//! `require_layer` makes that an error.
//!
//! One message is left out, and counted apart: with DEBUG, naga marks the SPIR-V of wgpu's
//! shaders as written in WGSL, a source language validation layers before 1.3.250 (Debian 12
//! ships 1.3.239) do not know, so they reject every module Bevy compiles. patchex's shaders are
//! compiled when patchex is built, without that mark.

use std::sync::Mutex;

use bevy::app::App;
use bevy::log::BoxedLayer;
use bevy::log::tracing::field::{Field, Visit};
use bevy::log::tracing::{Event, Level, Subscriber};
use bevy::log::tracing_subscriber::layer::{Context, Layer};

/// What the layer said so far.
static REPORTS: Mutex<Reports> = Mutex::new(Reports {
    messages: Vec::new(),
    unknown_source_language: 0,
    skipping: false,
});

/// What the layer says of a module whose OpSource names a language it does not know.
const UNKNOWN_SOURCE_LANGUAGE: &str = "SPIR-V module not valid: Invalid source language operand";

pub struct Reports {
    /// Every validation message, with its queues, command buffers and objects.
    pub messages: Vec<String>,
    /// Messages left out: Bevy's shaders marked as WGSL, to a layer that does not know it.
    pub unknown_source_language: usize,
    /// Whether the lines that follow belong to a message left out.
    skipping: bool,
}

/// The name of the Khronos validation layer.
const KHRONOS_VALIDATION: &std::ffi::CStr = c"VK_LAYER_KHRONOS_validation";

/// Fails unless the Khronos validation layer is installed, so that wgpu has loaded it.
pub fn require_layer(device: &wgpu::Device) -> Result<(), String> {
    // SAFETY: only the loader's entry is used, to list the layers.
    let layers = unsafe {
        let hal = device
            .as_hal::<wgpu::hal::api::Vulkan>()
            .ok_or("Bevy is not rendering through Vulkan")?;
        hal.shared_instance()
            .entry()
            .enumerate_instance_layer_properties()
            .map_err(|e| format!("cannot list Vulkan layers: {e}"))?
    };
    if layers
        .iter()
        .any(|layer| layer.layer_name_as_c_str() == Ok(KHRONOS_VALIDATION))
    {
        Ok(())
    } else {
        Err(
            "the Khronos validation layer is not installed (scripts/install-deps.sh installs it)"
                .to_owned(),
        )
    }
}

/// For `LogPlugin::custom_layer`.
pub fn layer(_app: &mut App) -> Option<BoxedLayer> {
    Some(Box::new(ValidationMessages))
}

/// The messages so far, and how many were left out.
pub fn reports() -> (Vec<String>, usize) {
    REPORTS
        .lock()
        .map(|reports| (reports.messages.clone(), reports.unknown_source_language))
        .unwrap_or_default()
}

struct ValidationMessages;

impl<S: Subscriber> Layer<S> for ValidationMessages {
    fn on_event(&self, event: &Event<'_>, _context: Context<'_, S>) {
        if *event.metadata().level() > Level::WARN {
            return;
        }
        let mut fields = Fields::default();
        event.record(&mut fields);
        // Events from the `log` crate carry their target as a field.
        let target = fields
            .log_target
            .as_deref()
            .unwrap_or(event.metadata().target());
        if !target.starts_with("wgpu_hal::vulkan") {
            return;
        }
        let Ok(mut reports) = REPORTS.lock() else {
            return;
        };
        // wgpu logs a message's queues, command buffers and objects as lines of their own,
        // indented: they belong to the message before.
        if fields.message.starts_with('\t') {
            let skipping = reports.skipping;
            if let Some(last) = reports.messages.last_mut().filter(|_| !skipping) {
                last.push('\n');
                last.push_str(&fields.message);
            }
        } else if fields.message.contains(UNKNOWN_SOURCE_LANGUAGE) {
            reports.unknown_source_language += 1;
            reports.skipping = true;
        } else {
            reports.messages.push(fields.message);
            reports.skipping = false;
        }
    }
}

#[derive(Default)]
struct Fields {
    message: String,
    log_target: Option<String>,
}

impl Visit for Fields {
    fn record_str(&mut self, field: &Field, value: &str) {
        match field.name() {
            "log.target" => self.log_target = Some(value.to_owned()),
            "message" => self.message = value.to_owned(),
            _ => {}
        }
    }

    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        if field.name() == "message" {
            self.message = format!("{value:?}");
        }
    }
}
