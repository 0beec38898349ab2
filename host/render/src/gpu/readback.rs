//! Reading a rendered picture back from the GPU: the copy into a buffer with padded
//! rows, the map and wait, the rows unpadded into RGBA.

use crate::image::RgbaImage;
use crate::RenderError;

/// Maps `buffer` (a copied `width × height` picture in `format` with rows of `padded_row`
/// bytes), waits for the GPU and returns the picture as RGBA.
pub(crate) fn read_buffer(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    padded_row: u32,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
) -> Result<RgbaImage, RenderError> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::Wait)
        .map_err(|e| RenderError::Gpu(e.to_string()))?;
    rx.recv()
        .map_err(|e| RenderError::Gpu(e.to_string()))?
        .map_err(|e| RenderError::Gpu(e.to_string()))?;
    let data = unpad_rows(&slice.get_mapped_range(), padded_row, width, format);
    buffer.unmap();
    Ok(RgbaImage::new(width, height, data))
}

/// Copies `texture` (`width × height`, 4 bytes per pixel) into `buffer` with rows of
/// `padded_row` bytes.
pub(crate) fn copy_to_buffer(
    enc: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    buffer: &wgpu::Buffer,
    padded_row: u32,
    width: u32,
    height: u32,
) {
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
}

/// Bytes per row of a `width`-pixel, 4-byte-per-pixel copy, padded as wgpu requires.
pub(crate) fn padded_row_bytes(width: u32) -> u32 {
    (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

/// Tightly packed RGBA bytes from padded rows of `format` pixels (BGRA formats are
/// swizzled to RGBA).
pub(crate) fn unpad_rows(
    mapped: &[u8],
    padded_row: u32,
    width: u32,
    format: wgpu::TextureFormat,
) -> Vec<u8> {
    let bgra = matches!(
        format,
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    );
    let row_bytes = (width * 4) as usize;
    let mut data = Vec::with_capacity(row_bytes * (mapped.len() / padded_row.max(1) as usize));
    for row in mapped.chunks(padded_row as usize) {
        let row = &row[..row_bytes.min(row.len())];
        if bgra {
            for px in row.chunks_exact(4) {
                data.extend_from_slice(&[px[2], px[1], px[0], px[3]]);
            }
        } else {
            data.extend_from_slice(row);
        }
    }
    data
}
