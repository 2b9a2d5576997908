//! egui's own triangles drawn by a lean pipeline of ours (`shaders/ui.wgsl`) on a software
//! rasteriser. Measured in the window under Xvfb on lavapipe (Mesa 22.3), egui-wgpu's
//! fragment shader was about 55% of all CPU time: lavapipe executes both sides of its
//! uniform branches (texture filtering by hand or not, dithering or not) on every pixel.
//!
//! How it fits in egui: at the end of a frame, the window takes the shapes out of egui's
//! layers, tessellates them itself into one [`UiBatch`], and puts back paint callbacks
//! ([`batch_callback`]) where they were, so that the order of drawing (and our 3D view's own
//! callback among egui's shapes) stays as it was. The callbacks draw the batch's meshes with
//! the font atlas, which the batch carries as a copy ([`AtlasCopy`]): egui hands its own
//! texture to egui-wgpu only after the frame, and may replace it then.

use super::kit::{self, ResourcePaint, resource_callback};
use eframe::egui::{self, epaint::ClippedPrimitive};
use eframe::egui_wgpu::ScreenDescriptor;
use eframe::wgpu;
use std::sync::Arc;

/// The font atlas as egui had it at the end of a frame (sRGB-encoded premultiplied RGBA).
pub struct AtlasCopy {
    pub size: [usize; 2],
    pub pixels: Vec<egui::Color32>,
}

/// One frame's worth of egui meshes, drawn by one or more callbacks (`runs`).
pub struct UiBatch {
    /// Per run: the tessellated shapes (meshes only) of one stretch of one layer.
    pub runs: Vec<Vec<ClippedPrimitive>>,
    pub atlas: Arc<AtlasCopy>,
}

impl UiBatch {
    /// All the batch's primitives (for counting what they ask of the rasteriser).
    pub fn primitives(&self) -> impl Iterator<Item = &ClippedPrimitive> {
        self.runs.iter().flatten()
    }
}

/// The paint callback drawing run `run` of `batch`, covering `screen` (in points).
pub fn batch_callback(batch: Arc<UiBatch>, run: usize, screen: egui::Rect) -> egui::PaintCallback {
    resource_callback(screen, BatchCallback { batch, run })
}

struct BatchCallback {
    batch: Arc<UiBatch>,
    run: usize,
}

/// Where one mesh lies in the uploaded buffers.
#[derive(Clone, Copy)]
struct Draw {
    clip: egui::Rect,
    first_index: u32,
    index_count: u32,
    base_vertex: i32,
}

/// The pipeline and the buffers, in egui-wgpu's callback resources.
pub struct UiPainter {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    screen: wgpu::Buffer,
    group: Option<wgpu::BindGroup>,
    atlas: Option<(Arc<AtlasCopy>, wgpu::Texture)>,
    vertices: Option<wgpu::Buffer>,
    indices: Option<wgpu::Buffer>,
    /// The batch whose meshes are in the buffers, and per run its draws.
    uploaded: Option<Arc<UiBatch>>,
    draws: Vec<Vec<Draw>>,
}

impl UiPainter {
    /// For a render pass with one sample, no depth, colour format `format` (eframe's and
    /// egui_kittest's passes with their default options).
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> UiPainter {
        let shader = kit::shader(device, "ui.wgsl", include_str!("../../shaders/ui.wgsl"));
        let layout = kit::bind_group_layout(
            device,
            "ui",
            &[
                (wgpu::ShaderStages::VERTEX, kit::uniform(false, 0)),
                (
                    wgpu::ShaderStages::FRAGMENT,
                    kit::texture(wgpu::TextureSampleType::Float { filterable: true }),
                ),
                (
                    wgpu::ShaderStages::FRAGMENT,
                    wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                ),
            ],
        );
        // egui's premultiplied blending, as egui-wgpu sets it.
        let blend = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::OneMinusDstAlpha,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let pipeline = kit::PipelineSpec {
            label: "ui",
            layout: &kit::pipeline_layout(device, "ui", &[&layout]),
            shader: &shader,
            vertex: "vs_ui",
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: size_of::<egui::epaint::Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x2, 2 => Uint32],
            })],
            cull: None,
            depth: None,
            fragment: Some((
                if format.is_srgb() { "fs_ui_srgb" } else { "fs_ui" },
                kit::color_target(format, Some(blend)),
            )),
        }
        .build(device);
        // The font atlas' own options (linear, clamped), as egui asks for it.
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("ui atlas"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let screen = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ui screen"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        UiPainter {
            pipeline,
            layout,
            sampler,
            screen,
            group: None,
            atlas: None,
            vertices: None,
            indices: None,
            uploaded: None,
            draws: Vec::new(),
        }
    }

    fn upload_atlas(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, atlas: &Arc<AtlasCopy>) {
        if self.atlas.as_ref().is_some_and(|(a, _)| Arc::ptr_eq(a, atlas)) {
            return;
        }
        let [w, h] = atlas.size.map(|s| s.max(1) as u32);
        let size = wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 };
        let reuse = self.atlas.as_ref().map(|(_, t)| t.clone()).filter(|t| t.size() == size);
        let texture = reuse.unwrap_or_else(|| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("ui atlas"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            })
        });
        if atlas.pixels.len() == (w * h) as usize {
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(&atlas.pixels),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * w),
                    rows_per_image: Some(h),
                },
                size,
            );
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        self.group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ui"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.screen.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
            ],
        }));
        self.atlas = Some((atlas.clone(), texture));
    }

    /// Uploads every run of `batch` (once per batch: its first callback does it for all).
    fn upload(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &ScreenDescriptor,
        batch: &Arc<UiBatch>,
    ) {
        if self.uploaded.as_ref().is_some_and(|b| Arc::ptr_eq(b, batch)) {
            return;
        }
        self.upload_atlas(device, queue, &batch.atlas);
        let ppp = screen.pixels_per_point.max(1e-3);
        let size_points = [
            screen.size_in_pixels[0] as f32 / ppp,
            screen.size_in_pixels[1] as f32 / ppp,
            0.0,
            0.0,
        ];
        queue.write_buffer(&self.screen, 0, bytemuck::cast_slice(&size_points));

        let mut vertices: Vec<egui::epaint::Vertex> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        self.draws.clear();
        for run in &batch.runs {
            let mut draws = Vec::with_capacity(run.len());
            for p in run {
                let egui::epaint::Primitive::Mesh(mesh) = &p.primitive else { continue };
                if mesh.indices.is_empty() {
                    continue;
                }
                draws.push(Draw {
                    clip: p.clip_rect,
                    first_index: indices.len() as u32,
                    index_count: mesh.indices.len() as u32,
                    base_vertex: vertices.len() as i32,
                });
                vertices.extend_from_slice(&mesh.vertices);
                indices.extend_from_slice(&mesh.indices);
            }
            self.draws.push(draws);
        }
        write_growing(
            device,
            queue,
            &mut self.vertices,
            bytemuck::cast_slice(&vertices),
            wgpu::BufferUsages::VERTEX,
            "ui vertices",
        );
        write_growing(
            device,
            queue,
            &mut self.indices,
            bytemuck::cast_slice(&indices),
            wgpu::BufferUsages::INDEX,
            "ui indices",
        );
        self.uploaded = Some(batch.clone());
    }

    fn paint(
        &self,
        batch: &Arc<UiBatch>,
        run: usize,
        info: &egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
    ) {
        if !self.uploaded.as_ref().is_some_and(|b| Arc::ptr_eq(b, batch)) {
            return;
        }
        let (Some(group), Some(vertices), Some(indices), Some(draws)) =
            (&self.group, &self.vertices, &self.indices, self.draws.get(run))
        else {
            return;
        };
        let [w, h] = info.screen_size_px;
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        for d in draws {
            let Some([x, y, sw, sh]) = scissor(d.clip, info.pixels_per_point, [w, h]) else {
                continue;
            };
            pass.set_scissor_rect(x, y, sw, sh);
            pass.draw_indexed(d.first_index..d.first_index + d.index_count, d.base_vertex, 0..1);
        }
    }
}

/// A clip rectangle in points as a scissor rectangle in pixels within the screen, or None
/// when nothing of it is on screen.
fn scissor(clip: egui::Rect, ppp: f32, screen: [u32; 2]) -> Option<[u32; 4]> {
    let px = |v: f32, max: u32| ((v * ppp).round().max(0.0) as u32).min(max);
    let (x0, y0) = (px(clip.min.x, screen[0]), px(clip.min.y, screen[1]));
    let (x1, y1) = (px(clip.max.x, screen[0]), px(clip.max.y, screen[1]));
    (x1 > x0 && y1 > y0).then_some([x0, y0, x1 - x0, y1 - y0])
}

/// Writes `data` into `buffer`, replacing it by one twice as large when it does not fit.
fn write_growing(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &mut Option<wgpu::Buffer>,
    data: &[u8],
    usage: wgpu::BufferUsages,
    label: &str,
) {
    // Buffer sizes and writes go in multiples of 4 bytes.
    let needed = (data.len() as u64).div_ceil(4) * 4;
    if buffer.as_ref().is_none_or(|b| b.size() < needed.max(4)) {
        *buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: needed.max(1024).next_power_of_two(),
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }));
    }
    if let Some(b) = buffer.as_ref().filter(|_| !data.is_empty()) {
        if data.len().is_multiple_of(4) {
            queue.write_buffer(b, 0, data);
        } else {
            let mut padded = data.to_vec();
            padded.resize(needed as usize, 0);
            queue.write_buffer(b, 0, &padded);
        }
    }
}

impl ResourcePaint for BatchCallback {
    type Resource = UiPainter;

    fn prepare(
        &self,
        painter: &mut UiPainter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
    ) {
        painter.upload(device, queue, screen, &self.batch);
    }

    fn paint(
        &self,
        painter: &UiPainter,
        info: &egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
    ) {
        painter.paint(&self.batch, self.run, info, pass);
    }
}

#[cfg(test)]
mod tests {
    use super::scissor;
    use eframe::egui::{Rect, pos2};

    #[test]
    fn scissors_are_clamped_to_the_screen_and_empty_ones_dropped() {
        let r = Rect::from_min_max(pos2(-5.0, 10.0), pos2(50.0, 500.0));
        assert_eq!(scissor(r, 2.0, [80, 600]), Some([0, 20, 80, 580]));
        assert_eq!(
            scissor(Rect::from_min_max(pos2(90.0, 0.0), pos2(95.0, 5.0)), 1.0, [80, 600]),
            None
        );
        assert_eq!(scissor(Rect::NOTHING, 1.0, [80, 600]), None);
    }
}
