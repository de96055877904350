//! Images in memory: 8-bit sRGB RGBA as the renderer reads them back, with PNG output
//! and the box-filter downsampling that turns a supersampled render into a reference.

use std::path::Path;

use crate::error::{Error, Result};

/// An 8-bit RGBA image in memory.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    pub data: Vec<u8>,
}

impl RgbaImage {
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.data[i],
            self.data[i + 1],
            self.data[i + 2],
            self.data[i + 3],
        ]
    }

    /// Rec. 709 luma of the (sRGB-encoded) pixel, 0..1.
    pub fn luma(&self, x: u32, y: u32) -> f32 {
        let [r, g, b, _] = self.pixel(x, y);
        (0.2126 * f32::from(r) + 0.7152 * f32::from(g) + 0.0722 * f32::from(b)) / 255.0
    }

    /// Writes a PNG through [`crate::files::write_output`]: a regular file (or a new
    /// one) through a temporary file renamed into place, so an interrupted or failed
    /// write never leaves half an image; a device, a FIFO or `-` (standard output)
    /// written directly, never replaced.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        let bytes = self.encode_png().map_err(|message| Error::ImageWrite {
            path: path.to_path_buf(),
            message,
        })?;
        crate::files::write_output(path, &bytes, "write the image")
    }

    /// The image as PNG bytes.
    pub fn encode_png(&self) -> std::result::Result<Vec<u8>, String> {
        let error = |e: &dyn std::fmt::Display| e.to_string();
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header().map_err(|e| error(&e))?;
        writer.write_image_data(&self.data).map_err(|e| error(&e))?;
        writer.finish().map_err(|e| error(&e))?;
        Ok(bytes)
    }
}

impl RgbaImage {
    /// Averages every `factor` × `factor` block in linear light (as an MSAA resolve of
    /// an sRGB target does). The size must be a multiple of `factor`.
    pub fn downsample(&self, factor: u32) -> Result<Self> {
        if factor == 0 || self.width % factor != 0 || self.height % factor != 0 {
            return Err(Error::Parameter(format!(
                "cannot downsample {}×{} by {factor}",
                self.width, self.height
            )));
        }
        let (w, h) = (self.width / factor, self.height / factor);
        let size = |width, height| crate::colour::Size { width, height };
        let data = crate::colour::resample(&self.data, size(self.width, self.height), size(w, h));
        Ok(Self {
            width: w,
            height: h,
            data,
        })
    }

    /// The RGB bytes, row after row (alpha dropped).
    pub fn rgb(&self) -> Vec<u8> {
        self.data
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect()
    }
}

/// Mean ꟻLIP error (NVIDIA's perceptual difference, 0 = identical, 1 = maximal) of
/// `test` against `reference`, at the default viewing condition (67 pixels per degree).
pub fn flip(reference: &RgbaImage, test: &RgbaImage) -> f64 {
    assert_eq!(
        (reference.width, reference.height),
        (test.width, test.height),
        "images differ in size"
    );
    let (w, h) = (reference.width, reference.height);
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &reference.rgb()),
        nv_flip::FlipImageRgb8::with_data(w, h, &test.rgb()),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    f64::from(nv_flip::FlipPool::from_image(&error).mean())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_in_linear_light() {
        // Half black, half white averages to linear 0.5, sRGB 188 (not 128).
        let image = RgbaImage {
            width: 2,
            height: 2,
            data: [[0, 0, 0, 255], [255, 255, 255, 255]]
                .repeat(2)
                .into_iter()
                .flatten()
                .collect(),
        };
        let small = image.downsample(2).unwrap();
        assert_eq!((small.width, small.height), (1, 1));
        assert_eq!(small.pixel(0, 0), [188, 188, 188, 255]);
        assert!(image.downsample(3).is_err());
    }
}
