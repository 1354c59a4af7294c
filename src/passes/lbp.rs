//! Local binary pattern of the warped frame (`shaders/lbp.wgsl`), an input of the networks.

use ash::vk;

use crate::passes::Texture;
use crate::shaders::lbp::{binding, Params};
use crate::vk::image::OwnedImage;
use crate::vk::recorder::{Pass, Recorder};

pub fn record(
    rec: &mut Recorder,
    pass: Pass,
    extent: vk::Extent2D,
    warped: Texture,
    lbp: &OwnedImage,
) {
    let bound = rec.bind(pass, |writes| {
        writes
            .image(binding::WARPED, warped)
            .image(binding::LBP, lbp)
    });
    let params = Params {
        extent: [extent.width, extent.height],
    };
    rec.dispatch(&bound, &params, extent);
}
