//! A plain RGBA8 image (sRGB bytes, rows top to bottom) and PNG writing.

use crate::RenderError;
use std::path::Path;

/// An 8-bit RGBA image, rows top to bottom, sRGB-encoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbaImage {
    width: u32,
    height: u32,
    data: Vec<u8>,
}

impl RgbaImage {
    /// An image from raw RGBA bytes (`width · height · 4` of them).
    ///
    /// # Panics
    /// If the length does not match.
    pub fn new(width: u32, height: u32, data: Vec<u8>) -> RgbaImage {
        assert_eq!(data.len(), width as usize * height as usize * 4);
        RgbaImage {
            width,
            height,
            data,
        }
    }

    /// Width, pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height, pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The raw RGBA bytes.
    pub fn as_bytes(&self) -> &[u8] {
        &self.data
    }

    /// The pixel at `(x, y)`; `None` outside.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize * self.width as usize + x as usize) * 4;
        Some([
            self.data[i],
            self.data[i + 1],
            self.data[i + 2],
            self.data[i + 3],
        ])
    }

    /// Encodes as PNG (RGB, the alpha is always opaque).
    pub fn to_png(&self) -> Result<Vec<u8>, RenderError> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, self.width, self.height);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            enc.set_compression(png::Compression::Best);
            enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
            let mut w = enc.write_header().map_err(|e| png_error("<memory>", e))?;
            let rgb: Vec<u8> = self
                .data
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            w.write_image_data(&rgb)
                .map_err(|e| png_error("<memory>", e))?;
        }
        Ok(out)
    }

    /// Writes a PNG file.
    pub fn save_png(&self, path: &Path) -> Result<(), RenderError> {
        let bytes = self.to_png()?;
        std::fs::write(path, bytes).map_err(|e| png_error(&path.display().to_string(), e))
    }
}

fn png_error(path: &str, e: impl std::fmt::Display) -> RenderError {
    RenderError::Png {
        path: path.to_string(),
        message: e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_and_png_signature() {
        let mut data = vec![0u8; 2 * 3 * 4];
        data[(2 + 1) * 4] = 200; // (1, 1) red
        let img = RgbaImage::new(2, 3, data);
        assert_eq!(img.pixel(1, 1), Some([200, 0, 0, 0]));
        assert_eq!(img.pixel(2, 0), None);
        let png = img.to_png().unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    }
}
