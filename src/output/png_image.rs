//! 8-bit RGB images as PNG: the benchmark plot and the window's screenshots.

use std::io::{self, Write};

/// Writes `rgb` (rows of `width` pixels, three bytes each, top row first)
/// as a PNG of `width` × `height`.
pub fn write_png(out: impl Write, width: u32, height: u32, rgb: &[u8]) -> io::Result<()> {
    let mut encoder = png::Encoder::new(out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(io::Error::other)?;
    writer.write_image_data(rgb).map_err(io::Error::other)?;
    writer.finish().map_err(io::Error::other)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_come_back_as_written() {
        let rgb: Vec<u8> = (0..2 * 3 * 3).map(|i| i as u8 * 10).collect();
        let mut file = Vec::new();
        write_png(&mut file, 3, 2, &rgb).unwrap();
        let mut reader = png::Decoder::new(io::Cursor::new(file)).read_info().unwrap();
        let mut back = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut back).unwrap();
        assert_eq!((info.width, info.height, info.color_type), (3, 2, png::ColorType::Rgb));
        assert_eq!(back, rgb);
        assert!(write_png(&mut Vec::new(), 3, 2, &rgb[1..]).is_err(), "too few bytes");
    }
}
