//! The table's wood grain (`assets/textures/table.png`, compiled in), with its mipmaps made
//! here so that the far table does not shimmer.

const TABLE_PNG: &[u8] = include_bytes!("../../assets/textures/table.png");

/// Halves a square grey image by averaging 2x2 blocks.
fn half(src: &[u8], n: usize) -> Vec<u8> {
    let m = n / 2;
    let mut out = vec![0u8; m * m];
    for y in 0..m {
        for x in 0..m {
            let s = |dx: usize, dy: usize| src[(2 * y + dy) * n + 2 * x + dx] as u32;
            out[y * m + x] = ((s(0, 0) + s(1, 0) + s(0, 1) + s(1, 1) + 2) / 4) as u8;
        }
    }
    out
}

/// Uploads the grain as an R8 texture with a full mip chain. The PNG is part of the binary,
/// so failing to decode it is a build defect: a flat grey texture stands in.
pub fn table_texture(device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::TextureView {
    let (mut data, mut n) = match image::load_from_memory(TABLE_PNG) {
        Ok(img) if img.width() == img.height() && img.width().is_power_of_two() => {
            let n = img.width() as usize;
            (img.into_luma8().into_raw(), n)
        }
        _ => (vec![128u8; 4], 2),
    };
    let levels = n.trailing_zeros() + 1;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("table grain"),
        size: wgpu::Extent3d { width: n as u32, height: n as u32, depth_or_array_layers: 1 },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for level in 0..levels {
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &data,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(n as u32), rows_per_image: Some(n as u32) },
            wgpu::Extent3d { width: n as u32, height: n as u32, depth_or_array_layers: 1 },
        );
        if n > 1 {
            data = half(&data, n);
            n /= 2;
        }
    }
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}
