//! The canvas's picture: a PNG data URL decoded to RGBA, and the counts the checks use.

use base64::Engine;
use std::collections::HashSet;
use std::path::Path;

/// An RGBA picture.
pub struct Picture {
    pub w: u32,
    pub h: u32,
    rgba: Vec<u8>,
}

impl Picture {
    /// Decodes `data:image/png;base64,…`.
    pub fn from_data_url(url: &str) -> Picture {
        let b64 = url
            .strip_prefix("data:image/png;base64,")
            .unwrap_or_else(|| panic!("not a PNG data URL: {:.40}", url));
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(b64)
            .expect("base64");
        let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder.read_info().expect("PNG header");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("PNG frame");
        buf.truncate(info.buffer_size());
        let rgba = match info.color_type {
            png::ColorType::Rgba => buf,
            png::ColorType::Rgb => buf
                .chunks(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect(),
            other => panic!("unexpected PNG colour type {other:?}"),
        };
        Picture {
            w: info.width,
            h: info.height,
            rgba,
        }
    }

    /// Writes the picture as a PNG (for a person to look at when a check fails).
    pub fn save(&self, path: &Path) {
        let file = std::fs::File::create(path).expect("create the PNG");
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), self.w, self.h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header()
            .and_then(|mut w| w.write_image_data(&self.rgba))
            .expect("write the PNG");
        eprintln!("canvas picture: {}", path.display());
    }

    fn rgb(&self, x: u32, y: u32) -> [i32; 3] {
        let i = 4 * (y as usize * self.w as usize + x as usize);
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2]].map(i32::from)
    }

    /// Pixels in `[x0, y0, x1, y1]` (clipped to the picture) for which `f` holds.
    pub fn count(&self, rect: [f32; 4], f: impl Fn([i32; 3]) -> bool) -> usize {
        let x0 = rect[0].max(0.0) as u32;
        let y0 = rect[1].max(0.0) as u32;
        let x1 = (rect[2].max(0.0) as u32).min(self.w);
        let y1 = (rect[3].max(0.0) as u32).min(self.h);
        (y0..y1)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .filter(|&(x, y)| f(self.rgb(x, y)))
            .count()
    }

    /// The number of distinct colours.
    pub fn distinct_colours(&self) -> usize {
        self.rgba
            .chunks(4)
            .map(|p| [p[0], p[1], p[2]])
            .collect::<HashSet<_>>()
            .len()
    }
}
