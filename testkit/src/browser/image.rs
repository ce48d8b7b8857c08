//! Screenshots as pixels: a PNG decoded to 8-bit RGBA, so that a test can read the color at a
//! point of the page.

use super::Error;

/// A decoded image: `width` × `height` pixels, four bytes (R, G, B, A) each, row by row from
/// the top left.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rgba {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

impl Rgba {
    /// Decodes a PNG of any color type and bit depth to 8-bit RGBA.
    pub fn from_png(png_bytes: &[u8]) -> Result<Rgba, Error> {
        let bad = |e: png::DecodingError| Error::Protocol(format!("decoding a screenshot: {e}"));
        let mut decoder = png::Decoder::new(png_bytes);
        decoder.set_transformations(png::Transformations::normalize_to_color8());
        let mut reader = decoder.read_info().map_err(bad)?;
        let mut buffer = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buffer).map_err(bad)?;
        buffer.truncate(info.buffer_size());
        let pixels = match info.color_type {
            png::ColorType::Rgba => buffer,
            png::ColorType::Rgb => buffer
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect(),
            png::ColorType::Grayscale => buffer.iter().flat_map(|&g| [g, g, g, 255]).collect(),
            png::ColorType::GrayscaleAlpha => buffer
                .chunks_exact(2)
                .flat_map(|p| [p[0], p[0], p[0], p[1]])
                .collect(),
            png::ColorType::Indexed => {
                return Err(Error::Protocol(
                    "decoding a screenshot: a palette image was not expanded".into(),
                ))
            }
        };
        Ok(Rgba {
            width: info.width,
            height: info.height,
            pixels,
        })
    }

    /// The color at (`x`, `y`) in image pixels (device pixels for a screenshot), or `None`
    /// outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let at = ((y as usize * self.width as usize) + x as usize) * 4;
        let p = self.pixels.get(at..at + 4)?;
        Some([p[0], p[1], p[2], p[3]])
    }

    /// Every pixel (`x`, `y`) whose color `keep` accepts, row by row.
    pub fn points(&self, keep: impl Fn([u8; 4]) -> bool) -> Vec<(u32, u32)> {
        (0..self.height)
            .flat_map(|y| (0..self.width).map(move |x| (x, y)))
            .filter(|&(x, y)| self.pixel(x, y).is_some_and(&keep))
            .collect()
    }
}

/// Whether `a` and `b` differ by at most `tolerance` in each of R, G and B (alpha is not
/// compared): software rendering and color conversion may move a channel by a step or two.
pub fn near(a: [u8; 4], b: [u8; 3], tolerance: u8) -> bool {
    a.iter().zip(b).all(|(&x, y)| x.abs_diff(y) <= tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn encode(width: u32, height: u32, color: png::ColorType, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(color);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().expect("a header");
        writer.write_image_data(data).expect("image data");
        writer.finish().expect("finished");
        out
    }

    #[test]
    fn an_rgb_png_reads_back_as_rgba_pixels() {
        let png = encode(2, 1, png::ColorType::Rgb, &[255, 0, 0, 0, 0, 255]);
        let image = Rgba::from_png(&png).expect("decodes");
        assert_eq!((image.width, image.height), (2, 1));
        assert_eq!(image.pixel(0, 0), Some([255, 0, 0, 255]));
        assert_eq!(image.pixel(1, 0), Some([0, 0, 255, 255]));
        assert_eq!(image.pixel(2, 0), None);
        assert_eq!(image.pixel(0, 1), None);
    }

    #[test]
    fn not_a_png_is_an_error() {
        assert!(Rgba::from_png(b"not a png").is_err());
    }

    #[test]
    fn near_allows_the_tolerance_and_no_more() {
        assert!(near([10, 20, 30, 0], [12, 18, 30], 2));
        assert!(!near([10, 20, 30, 255], [13, 20, 30], 2));
    }
}
