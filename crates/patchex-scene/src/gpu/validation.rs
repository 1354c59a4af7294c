//! Collects Khronos validation messages through a debug-utils messenger, so tests can fail on
//! any of them instead of scraping stderr.

use ash::vk;
use std::ffi::{c_void, CStr};
use std::sync::{Arc, Mutex};

pub(crate) type MessageLog = Arc<Mutex<Vec<String>>>;

pub(crate) fn messenger_info(log: &MessageLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(Arc::as_ptr(log) as *mut c_void)
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: `user_data` is the `MessageLog` that the `Gpu` keeps alive for as long as the
    // messenger exists, and `data` is valid for the duration of the callback.
    let (log, data) = unsafe { (&*(user_data as *const Mutex<Vec<String>>), &*data) };
    let text = if data.p_message.is_null() {
        String::from("(no message)")
    } else {
        // SAFETY: the layer passes a NUL-terminated string.
        unsafe { CStr::from_ptr(data.p_message) }
            .to_string_lossy()
            .into_owned()
    };
    if let Ok(mut messages) = log.lock() {
        messages.push(format!("{severity:?} {kind:?}: {text}"));
    }
    vk::FALSE
}
