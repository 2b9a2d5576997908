//! The scene renderer: a shadow-map pass and a colour + depth pass into its own offscreen
//! target, then (inside egui) a copy of that target into the 3D view's rectangle. Headless
//! renders read the same target back.

use super::mesh::{self, MeshData};
use super::pipelines::{Blit, COLOR_FORMAT, DEPTH_FORMAT, OBJECT_SIZE, Pipelines};
use super::scene::{BodyDraw, SceneFrame, TraceSegment};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};
use std::num::NonZeroU64;
use wgpu::util::DeviceExt;

const SHADOW_SIZE: u32 = 1024;
/// Uniform slots per object (table and bodies), 256 bytes apart (the dynamic-offset alignment).
const OBJECT_STRIDE: u64 = 256;
const MAX_OBJECTS: usize = 8;
/// Linear RGB of the space beyond the table.
pub const BACKGROUND: [f32; 3] = [0.62, 0.68, 0.76];
const TABLE_COLOR: [f32; 3] = [0.56, 0.40, 0.25];
/// Depth pushed back (clip-space z per w) for a body that yields: about 1% of the body's
/// radius at the default camera distance (near plane at 2% of it), invisible except where
/// two bodies' surfaces would otherwise fight.
const YIELD_DEPTH: f32 = 2e-5;
/// Direction towards the light (normalised in use): high, from behind on the left, so that
/// the default camera (in front) sees the shadow fall towards it.
const LIGHT_DIR: [f32; 3] = [-0.55, 0.45, 0.8];

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    light_view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light_dir: [f32; 4],
    table: [f32; 4],
    fade_center: [f32; 4],
    contacts: [[f32; 4]; 2],
    background: [f32; 4],
    shade_rect: [f32; 4],
    table_srgb: [f32; 4],
    background_srgb: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ObjectUniform {
    model: [[f32; 4]; 4],
    color: [f32; 4],
    material: [f32; 4],
    _pad: [f32; 40],
}

/// A body's mesh: its geometry and, for a film, its mark discs.
type MeshKey = ([u32; 3], Option<[u32; 14]>);

struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
}

impl GpuMesh {
    fn new(device: &wgpu::Device, m: &MeshData, label: &str) -> GpuMesh {
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(&m.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(&m.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        GpuMesh { vertices, indices, count: m.indices.len() as u32 }
    }
}

struct Target {
    size: [u32; 2],
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    blit_group: Option<wgpu::BindGroup>,
}

/// What one view needs of its own: several views are prepared before any is drawn, so each
/// has its own uniforms, traces and target.
struct Slot {
    globals: wgpu::Buffer,
    globals_group: wgpu::BindGroup,
    objects: wgpu::Buffer,
    objects_group: wgpu::BindGroup,
    traces: wgpu::Buffer,
    trace_capacity: usize,
    target: Option<Target>,
}

/// The number of views (slots) one renderer serves: one, or two side by side.
pub const MAX_VIEWS: usize = 2;

pub struct SceneRenderer {
    pipes: Pipelines,
    blit: Option<Blit>,
    textures_group: wgpu::BindGroup,
    shadow_view: wgpu::TextureView,
    table: GpuMesh,
    bodies: Vec<(MeshKey, GpuMesh)>,
    slots: Vec<Slot>,
}

fn srgb_encode(x: f32) -> f32 {
    if x <= 0.0031308 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 }
}

impl SceneRenderer {
    /// Builds the pipelines and the shadow map. `output_format`: the format of the render pass that
    /// [`SceneRenderer::paint`] draws into (egui's), or None for headless use only.
    pub fn new(device: &wgpu::Device, output_format: Option<wgpu::TextureFormat>) -> SceneRenderer {
        let pipes = Pipelines::new(device, size_of::<Globals>() as u64);
        let shadow = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d {
                width: SHADOW_SIZE,
                height: SHADOW_SIZE,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let shadow_view = shadow.create_view(&wgpu::TextureViewDescriptor::default());
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let textures_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow map"),
            layout: &pipes.textures_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&shadow_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&shadow_sampler),
                },
            ],
        });
        let blit = output_format.map(|f| Blit::new(device, f));
        let mut r = SceneRenderer {
            pipes,
            blit,
            textures_group,
            shadow_view,
            table: GpuMesh::new(device, &mesh::table_mesh(), "table"),
            bodies: Vec::new(),
            slots: Vec::new(),
        };
        for _ in 0..MAX_VIEWS {
            let slot = r.new_slot(device);
            r.slots.push(slot);
        }
        r
    }

    fn new_slot(&self, device: &wgpu::Device) -> Slot {
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &self.pipes.globals_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: globals.as_entire_binding() }],
        });
        let objects = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("objects"),
            size: OBJECT_STRIDE * MAX_OBJECTS as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let objects_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("objects"),
            layout: &self.pipes.objects_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &objects,
                    offset: 0,
                    size: NonZeroU64::new(OBJECT_SIZE),
                }),
            }],
        });
        Slot {
            globals,
            globals_group,
            objects,
            objects_group,
            traces: trace_buffer(device, 1024),
            trace_capacity: 1024,
            target: None,
        }
    }

    fn ensure_target(&mut self, device: &wgpu::Device, slot: usize, size: [u32; 2]) {
        if self.slots[slot].target.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        let extent = wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 };
        let color = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("scene colour"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let depth = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("scene depth"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let color_view = color.create_view(&wgpu::TextureViewDescriptor::default());
        let blit_group = self.blit.as_ref().map(|b| b.group(device, &color_view));
        self.slots[slot].target = Some(Target {
            size,
            color,
            color_view,
            depth_view: depth.create_view(&wgpu::TextureViewDescriptor::default()),
            blit_group,
        });
    }

    /// Meshes for the bodies `drawn`, made when missing; returns their indices in `self.bodies`.
    fn ensure_meshes(&mut self, device: &wgpu::Device, drawn: &[BodyDraw]) -> Vec<usize> {
        let keys: Vec<MeshKey> =
            drawn.iter().map(|b| (b.geometry.key(), b.discs.map(|d| d.key()))).collect();
        // A slider dragging through sizes makes a new mesh per size: keep only a few, never
        // one this frame uses.
        if self.bodies.len() + keys.len() > 6 {
            self.bodies.retain(|(k, _)| keys.contains(k));
        }
        for (b, key) in drawn.iter().zip(&keys) {
            if !self.bodies.iter().any(|(k, _)| k == key) {
                let mesh = match &b.discs {
                    None => mesh::body_mesh(&b.geometry),
                    Some(d) => {
                        let mut m = mesh::bare_body_mesh(&b.geometry);
                        m.append(d.mesh(&b.geometry));
                        m
                    }
                };
                self.bodies.push((*key, GpuMesh::new(device, &mesh, "body")));
            }
        }
        keys.iter().filter_map(|k| self.bodies.iter().position(|(b, _)| b == k)).collect()
    }

    /// Renders `frame` at `size` pixels into the offscreen target of view `slot` (below
    /// [`MAX_VIEWS`]; others are ignored), recording into `encoder`.
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        slot: usize,
        frame: &SceneFrame,
        size: [u32; 2],
    ) {
        if slot >= self.slots.len() {
            return;
        }
        let size = [size[0].max(1), size[1].max(1)];
        self.ensure_target(device, slot, size);
        let scale = frame.scale.max(1e-6);
        let cam = &frame.camera;
        let cam_distance = (cam.eye - cam.target).length();
        let fade_radius = (60.0 * scale).max(4.0 * cam_distance);
        let aspect = size[0] as f32 / size[1] as f32;
        let view_proj = cam.proj_matrix(aspect, 3.0 * fade_radius) * cam.view_matrix();
        let light = Vec3::from(LIGHT_DIR).normalize();

        // The shadow map covers the bodies (their centres and a margin for their size).
        let n = frame.bodies.len().max(1) as f32;
        let centre =
            frame.bodies.iter().map(|b| b.world_from_ring.w_axis.truncate()).sum::<Vec3>() / n;
        let centre = Vec3::new(centre.x, centre.y, 0.0);
        let reach = frame
            .bodies
            .iter()
            .map(|b| {
                let c = b.world_from_ring.w_axis.truncate();
                Vec3::new(c.x - centre.x, c.y - centre.y, 0.0).length()
                    + b.geometry.r
                    + b.geometry.h
            })
            .fold(scale, f32::max)
            * 1.4;
        let light_view =
            glam::camera::rh::view::look_at_mat4(centre + light * 4.0 * reach, centre, Vec3::Z);
        let light_proj = glam::camera::rh::proj::directx::orthographic(
            -reach,
            reach,
            -reach,
            reach,
            0.01 * reach,
            8.0 * reach,
        );
        let light_view_proj = light_proj * light_view;

        let mut contacts = [[0.0f32; 4]; 2];
        for (slot, b) in contacts.iter_mut().zip(&frame.bodies) {
            *slot = [b.contact.x, b.contact.y, 0.22 * b.geometry.r, 0.45];
        }
        let globals = Globals {
            view_proj: view_proj.to_cols_array_2d(),
            light_view_proj: light_view_proj.to_cols_array_2d(),
            eye: cam.eye.extend(1.0).to_array(),
            light_dir: light.extend(0.0).to_array(),
            table: [frame.grid_spacing, fade_radius, 0.0, scale],
            fade_center: [
                frame.focus.x,
                frame.focus.y,
                2.0 * reach / SHADOW_SIZE as f32,
                cam.pixel_angle(size[1]),
            ],
            contacts,
            background: Vec3::from(BACKGROUND).extend(1.0).to_array(),
            shade_rect: shade_rect(&frame.bodies, light),
            table_srgb: {
                // As the table shader lit it: ambient plus the sun from its height.
                let lit = 0.45 + 0.6 * light.z;
                [
                    srgb_encode(TABLE_COLOR[0] * lit),
                    srgb_encode(TABLE_COLOR[1] * lit * 0.96),
                    srgb_encode(TABLE_COLOR[2] * lit * 0.90),
                    1.0,
                ]
            },
            background_srgb: [
                srgb_encode(BACKGROUND[0]),
                srgb_encode(BACKGROUND[1]),
                srgb_encode(BACKGROUND[2]),
                1.0,
            ],
        };
        queue.write_buffer(&self.slots[slot].globals, 0, bytemuck::bytes_of(&globals));

        // Object 0: the table, a square centred under the focus; then the bodies.
        let table_model = Mat4::from_translation(frame.focus.extend(0.0))
            * Mat4::from_scale(Vec3::splat(fade_radius));
        let mut objects = vec![ObjectUniform {
            model: table_model.to_cols_array_2d(),
            color: Vec3::from(TABLE_COLOR).extend(1.0).to_array(),
            material: [0.0, 1.0, 0.0, 0.0],
            _pad: [0.0; 40],
        }];
        let drawn = &frame.bodies[..frame.bodies.len().min(MAX_OBJECTS - 1)];
        let meshes = self.ensure_meshes(device, drawn);
        for b in drawn {
            objects.push(ObjectUniform {
                model: b.world_from_ring.to_cols_array_2d(),
                color: Vec4::from((Vec3::from(b.color), 1.0)).to_array(),
                material: [0.85, 60.0, 0.6, if b.yields { YIELD_DEPTH } else { 0.0 }],
                _pad: [0.0; 40],
            });
        }
        let mut bytes = vec![0u8; OBJECT_STRIDE as usize * objects.len()];
        for (k, o) in objects.iter().enumerate() {
            let at = k * OBJECT_STRIDE as usize;
            bytes[at..at + size_of::<ObjectUniform>()].copy_from_slice(bytemuck::bytes_of(o));
        }
        let view = &mut self.slots[slot];
        queue.write_buffer(&view.objects, 0, &bytes);
        if frame.traces.len() > view.trace_capacity {
            view.trace_capacity = frame.traces.len().next_power_of_two();
            view.traces = trace_buffer(device, view.trace_capacity);
        }
        if !frame.traces.is_empty() {
            queue.write_buffer(&view.traces, 0, bytemuck::cast_slice(&frame.traces));
        }
        let trace_count = frame.traces.len() as u32;

        let view = &self.slots[slot];
        let Some(target) = &view.target else { return };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.shadow_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipes.shadow);
            pass.set_bind_group(0, &view.globals_group, &[]);
            self.draw_bodies(&mut pass, view, &meshes);
        }
        let bg = BACKGROUND.map(|c| srgb_encode(c) as f64);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.color_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r: bg[0], g: bg[1], b: bg[2], a: 1.0 }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &target.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &view.globals_group, &[]);
        pass.set_bind_group(2, &self.textures_group, &[]);
        pass.set_pipeline(&self.pipes.table);
        pass.set_bind_group(1, &view.objects_group, &[0]);
        pass.set_vertex_buffer(0, self.table.vertices.slice(..));
        pass.set_index_buffer(self.table.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.table.count, 0, 0..1);
        if trace_count > 0 {
            pass.set_pipeline(&self.pipes.trace);
            pass.set_vertex_buffer(0, view.traces.slice(..));
            pass.draw(0..6, 0..trace_count);
        }
        if !meshes.is_empty() {
            pass.set_pipeline(&self.pipes.shade);
            pass.draw(0..6, 0..1);
        }
        pass.set_pipeline(&self.pipes.body);
        self.draw_bodies(&mut pass, view, &meshes);
    }

    /// Draws the bodies (objects 1.. of `view`, meshes `meshes`) with the pipeline set.
    fn draw_bodies(&self, pass: &mut wgpu::RenderPass<'_>, view: &Slot, meshes: &[usize]) {
        for (k, &m) in meshes.iter().enumerate() {
            let mesh = &self.bodies[m].1;
            pass.set_bind_group(
                1,
                &view.objects_group,
                &[(k as u64 + 1) as u32 * OBJECT_STRIDE as u32],
            );
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.count, 0, 0..1);
        }
    }

    /// Draws view `slot`'s last frame into `pass` (egui's, whose viewport is the 3D view).
    pub fn paint(&self, slot: usize, pass: &mut wgpu::RenderPass<'_>) {
        let target = self.slots.get(slot).and_then(|s| s.target.as_ref());
        let (Some(blit), Some(group)) = (&self.blit, target.and_then(|t| t.blit_group.as_ref()))
        else {
            return;
        };
        pass.set_pipeline(&blit.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// The offscreen colour texture of view `slot`'s last frame (for reading back).
    pub fn color_texture(&self, slot: usize) -> Option<&wgpu::Texture> {
        self.slots.get(slot).and_then(|s| s.target.as_ref()).map(|t| &t.color)
    }
}

/// The square of table that can be in a body's shadow or near its contact: around where the
/// sun projects the centre of mass, half a side of the body's reach (none without bodies).
fn shade_rect(bodies: &[BodyDraw], light: Vec3) -> [f32; 4] {
    let mut lo = glam::Vec2::splat(f32::INFINITY);
    let mut hi = glam::Vec2::splat(f32::NEG_INFINITY);
    for b in bodies {
        let c = b.world_from_ring.w_axis.truncate();
        // Where the sun's ray through the centre of mass meets the table.
        let shadow = c.truncate() - light.truncate() * (c.z / light.z.max(0.2));
        let reach = 1.15 * (b.geometry.r + 0.5 * b.geometry.h);
        for p in [c.truncate(), shadow] {
            lo = lo.min(p - reach);
            hi = hi.max(p + reach);
        }
    }
    if bodies.is_empty() {
        return [0.0; 4];
    }
    let centre = 0.5 * (lo + hi);
    [centre.x, centre.y, 0.5 * (hi - lo).max_element(), 0.0]
}

fn trace_buffer(device: &wgpu::Device, capacity: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("traces"),
        size: (capacity * size_of::<TraceSegment>()) as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
