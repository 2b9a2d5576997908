//! Rendering without a window: a device of its own, the scene or a whole egui UI into an
//! offscreen texture, read back as an RGBA image.

use super::pipelines::COLOR_FORMAT;
use super::renderer::SceneRenderer;
use super::scene::SceneFrame;
use eframe::{egui, egui_wgpu};
use image::RgbaImage;
use std::time::Duration;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum RenderError {
    #[error(
        "no Vulkan graphics adapter found ({0}); ringlab draws through Vulkan: install a driver \
         (the software one, lavapipe, is in Debian's mesa-vulkan-drivers and libvulkan1)"
    )]
    NoAdapter(String),
    #[error("the graphics device could not be opened: {0}")]
    Device(String),
    #[error("reading the picture back from the graphics device failed: {0}")]
    Readback(String),
    #[error("size {0}x{1} is not a picture size (1 to {2} pixels a side)")]
    Size(u32, u32, u32),
}

/// A graphics device for rendering without a window.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: wgpu::AdapterInfo,
}

const WAIT: Duration = Duration::from_secs(30);

impl Gpu {
    /// Opens the first Vulkan adapter wgpu offers (`VK_DRIVER_FILES` picks lavapipe).
    pub fn new() -> Result<Gpu, RenderError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = wgpu::Backends::VULKAN;
        let instance = wgpu::Instance::new(desc);
        let adapter =
            pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
                .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("ringlab headless"),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(Gpu { device, queue, adapter: adapter.get_info() })
    }

    pub fn max_size(&self) -> u32 {
        self.device.limits().max_texture_dimension_2d
    }

    fn check_size(&self, w: u32, h: u32) -> Result<(), RenderError> {
        let max = self.max_size();
        if w == 0 || h == 0 || w > max || h > max {
            return Err(RenderError::Size(w, h, max));
        }
        Ok(())
    }

    /// Renders the 3D scene alone.
    pub fn render_scene(
        &self,
        renderer: &mut SceneRenderer,
        frame: &SceneFrame,
        size: [u32; 2],
    ) -> Result<RgbaImage, RenderError> {
        self.check_size(size[0], size[1])?;
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("scene") });
        renderer.render(&self.device, &self.queue, &mut encoder, 0, frame, size);
        self.queue.submit([encoder.finish()]);
        let texture = renderer
            .color_texture(0)
            .ok_or_else(|| RenderError::Readback("nothing was rendered".into()))?;
        read_texture(&self.device, &self.queue, texture)
    }
}

/// Copies an Rgba8 texture into an image (rows padded to 256 bytes on the way).
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<RgbaImage, RenderError> {
    let (w, h) = (texture.width(), texture.height());
    let row = 4 * w;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: (padded * h) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder =
        device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    let index = queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::Wait { submission_index: Some(index), timeout: Some(WAIT) })
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    match rx.recv_timeout(WAIT) {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(RenderError::Readback(e.to_string())),
        Err(e) => return Err(RenderError::Readback(e.to_string())),
    }
    let data = slice.get_mapped_range().map_err(|e| RenderError::Readback(e.to_string()))?;
    let mut pixels = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        let at = y * padded as usize;
        pixels.extend_from_slice(&data[at..at + row as usize]);
    }
    drop(data);
    buffer.unmap();
    RgbaImage::from_raw(w, h, pixels)
        .ok_or_else(|| RenderError::Readback("wrong number of bytes".into()))
}

/// egui drawn offscreen: the whole app or one panel, for `ringlab render --view app|top` and
/// the benchmarks. The scene renderer sits in egui-wgpu's callback resources, as in the window.
pub struct UiRenderer {
    pub ctx: egui::Context,
    renderer: egui_wgpu::Renderer,
    /// Whether [`UiRenderer::render`] counts what egui asks of the rasteriser (it costs a
    /// millisecond or two a frame), and the count of the last frame rendered with it on.
    pub count_drawing: bool,
    pub last_stats: super::ui_stats::UiStats,
}

impl UiRenderer {
    pub fn new(gpu: &Gpu) -> UiRenderer {
        let mut renderer = egui_wgpu::Renderer::new(
            &gpu.device,
            COLOR_FORMAT,
            egui_wgpu::RendererOptions { dithering: false, ..Default::default() },
        );
        renderer.callback_resources.insert(SceneRenderer::new(&gpu.device, Some(COLOR_FORMAT)));
        renderer
            .callback_resources
            .insert(super::ui_painter::UiPainter::new(&gpu.device, COLOR_FORMAT));
        let ctx = egui::Context::default();
        ctx.all_styles_mut(|s| {
            s.animation_time = 0.0;
            s.visuals.text_cursor.blink = false;
        });
        super::adapter::adapt_to_adapter(&ctx, &gpu.adapter);
        UiRenderer { ctx, renderer, count_drawing: false, last_stats: Default::default() }
    }

    /// Runs `ui` for `passes` frames on a `size`-pixel screen (pixels per point 1; layout
    /// settles after two or three), renders the last, and reads it back.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        size: [u32; 2],
        passes: usize,
        mut ui: impl FnMut(&mut egui::Ui),
    ) -> Result<RgbaImage, RenderError> {
        gpu.check_size(size[0], size[1])?;
        let screen =
            egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(size[0] as f32, size[1] as f32));
        let mut output = None;
        for k in 0..passes.max(1) {
            let mut input = egui::RawInput { screen_rect: Some(screen), ..Default::default() };
            input.time = Some(k as f64 / 60.0);
            if let Some(v) = input.viewports.get_mut(&egui::ViewportId::ROOT) {
                v.native_pixels_per_point = Some(1.0);
            }
            let out = self.ctx.run_ui(input, &mut ui);
            for (id, deltas) in &out.textures_delta.set {
                for delta in deltas {
                    self.renderer.update_texture(&gpu.device, &gpu.queue, *id, delta);
                }
            }
            for id in &out.textures_delta.free {
                self.renderer.free_texture(id);
            }
            output = Some(out);
        }
        let Some(output) = output else { return Err(RenderError::Readback("no frame".into())) };
        let jobs = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        if self.count_drawing {
            // What egui-wgpu draws, and what the lean painter draws for it (on lavapipe).
            let batch = super::lean_paint::last_batch(&self.ctx);
            let ours: Vec<_> = batch.iter().flat_map(|b| b.primitives().cloned()).collect();
            self.last_stats =
                super::ui_stats::UiStats::of(&jobs).plus(&super::ui_stats::UiStats::of(&ours));
        }
        let desc = egui_wgpu::ScreenDescriptor {
            size_in_pixels: size,
            pixels_per_point: output.pixels_per_point,
        };
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("ui"),
            size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        // The window clears to the panels' colour (they are not filled); so does this.
        let [r, g, b, _] =
            self.ctx.global_style().visuals.panel_fill.to_normalized_gamma_f32().map(f64::from);
        let clear = wgpu::Color { r, g, b, a: 1.0 };
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("ui") });
        let extra =
            self.renderer.update_buffers(&gpu.device, &gpu.queue, &mut encoder, &jobs, &desc);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("ui"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(clear),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime();
            self.renderer.render(&mut pass, &jobs, &desc);
        }
        gpu.queue.submit(extra.into_iter().chain([encoder.finish()]));
        read_texture(&gpu.device, &gpu.queue, &texture)
    }
}
