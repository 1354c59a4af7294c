//! Decoded textures as RGBA8 with a CPU-built mip chain.

/// How a texture is sampled: colour data is sRGB-encoded, everything else is linear.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureRole {
    Color,
    Data,
}

pub struct TextureData {
    pub width: u32,
    pub height: u32,
    pub role: TextureRole,
    /// Mip levels from full size down to 1x1, each tightly packed RGBA8.
    pub mips: Vec<Vec<u8>>,
}

impl TextureData {
    pub fn from_rgba8(width: u32, height: u32, pixels: Vec<u8>, role: TextureRole) -> Self {
        let mut mips = vec![pixels];
        let (mut w, mut h) = (width, height);
        while w > 1 || h > 1 {
            let next = downsample(mips.last().expect("at least one level"), w, h);
            w = (w / 2).max(1);
            h = (h / 2).max(1);
            mips.push(next);
        }
        Self {
            width,
            height,
            role,
            mips,
        }
    }

    /// A 1x1 texture standing in for a missing map, so every material binds the same layout.
    pub fn solid(rgba: [u8; 4], role: TextureRole) -> Self {
        Self::from_rgba8(1, 1, rgba.to_vec(), role)
    }

    pub fn mip_size(&self, level: usize) -> (u32, u32) {
        ((self.width >> level).max(1), (self.height >> level).max(1))
    }
}

/// 2x2 box filter; an odd last row or column is folded into its neighbour by clamping.
fn downsample(pixels: &[u8], width: u32, height: u32) -> Vec<u8> {
    let (out_w, out_h) = ((width / 2).max(1), (height / 2).max(1));
    let mut out = Vec::with_capacity((out_w * out_h * 4) as usize);
    for y in 0..out_h {
        for x in 0..out_w {
            for channel in 0..4 {
                let mut sum = 0u32;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (x * 2 + dx).min(width - 1);
                    let sy = (y * 2 + dy).min(height - 1);
                    sum += u32::from(pixels[((sy * width + sx) * 4 + channel) as usize]);
                }
                out.push(((sum + 2) / 4) as u8);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_chain_reaches_one_pixel_and_averages() {
        let pixels = [
            [0u8, 0, 0, 255],
            [200, 100, 40, 255],
            [100, 0, 0, 255],
            [100, 100, 0, 255],
        ]
        .iter()
        .flat_map(|p| p.iter().copied())
        .chain(std::iter::repeat_n(0u8, 8 * 4 - 16))
        .collect();
        let texture = TextureData::from_rgba8(4, 2, pixels, TextureRole::Data);
        assert_eq!(texture.mips.len(), 3);
        assert_eq!(texture.mip_size(2), (1, 1));
        // Level 1 texel 0 averages texels (0,0),(1,0),(0,1),(1,1): 200/4 = 50 in red.
        assert_eq!(texture.mips[1][0], 50);
        assert_eq!(texture.mips[1].len(), 2 * 4);
    }
}
