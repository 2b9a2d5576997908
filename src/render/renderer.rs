//! The scene renderer: a shadow-map pass and a colour + depth pass into its own offscreen
//! target, then (inside egui) a copy of that target into the 3D view's rectangle. Headless
//! renders read the same target back.

use super::mesh::{self, BodyGeometry, MeshData, Vertex};
use super::scene::{BodyDraw, SceneFrame, TraceSegment};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};
use std::num::NonZeroU64;
use wgpu::util::DeviceExt;

/// The offscreen colour format: 8-bit, holding the sRGB-encoded values the shaders write (an
/// sRGB view that encodes on write measured slower on lavapipe than the shaders' own cheap
/// encoding).
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DRAW_FORMAT: wgpu::TextureFormat = COLOR_FORMAT;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const SHADOW_SIZE: u32 = 1024;
/// Uniform slots per object (table and bodies), 256 bytes apart (the dynamic-offset alignment).
const OBJECT_STRIDE: u64 = 256;
const MAX_OBJECTS: usize = 8;
/// Linear RGB of the space beyond the table.
pub const BACKGROUND: [f32; 3] = [0.62, 0.68, 0.76];
const TABLE_COLOR: [f32; 3] = [0.56, 0.40, 0.25];
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

struct Blit {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
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
    body_pipeline: wgpu::RenderPipeline,
    table_pipeline: wgpu::RenderPipeline,
    trace_pipeline: wgpu::RenderPipeline,
    shade_pipeline: wgpu::RenderPipeline,
    shadow_pipeline: wgpu::RenderPipeline,
    blit: Option<Blit>,
    globals_layout: wgpu::BindGroupLayout,
    objects_layout: wgpu::BindGroupLayout,
    textures_group: wgpu::BindGroup,
    shadow_view: wgpu::TextureView,
    table: GpuMesh,
    bodies: Vec<([u32; 3], GpuMesh)>,
    slots: Vec<Slot>,
}

fn srgb_encode(x: f32) -> f32 {
    if x <= 0.0031308 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 }
}

fn uniform_entry(binding: u32, dynamic: bool, size: u64, vis: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: vis,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: dynamic,
            min_binding_size: NonZeroU64::new(size),
        },
        count: None,
    }
}

impl SceneRenderer {
    /// Builds the pipelines. `output_format`: the format of the render pass that
    /// [`SceneRenderer::paint`] draws into (egui's), or None for headless use only.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, output_format: Option<wgpu::TextureFormat>) -> SceneRenderer {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/scene.wgsl").into()),
        });
        let both = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT;
        let globals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[uniform_entry(0, false, size_of::<Globals>() as u64, both)],
        });
        let objects_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("object"),
            entries: &[uniform_entry(0, true, 96, both)],
        });
        let frag = wgpu::ShaderStages::FRAGMENT;
        let textures_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene textures"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: frag,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: frag,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: frag,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: frag,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });

        let shadow = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d { width: SHADOW_SIZE, height: SHADOW_SIZE, depth_or_array_layers: 1 },
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
        let table_view = super::texture::table_texture(device, queue);
        let table_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("table"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let textures_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene textures"),
            layout: &textures_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&shadow_view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&shadow_sampler) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&table_view) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::Sampler(&table_sampler) },
            ],
        });

        let main_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&globals_layout), Some(&objects_layout), Some(&textures_layout)],
            immediate_size: 0,
        });
        let shadow_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow"),
            bind_group_layouts: &[Some(&globals_layout), Some(&objects_layout)],
            immediate_size: 0,
        });

        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4],
        };
        let trace_layout = wgpu::VertexBufferLayout {
            array_stride: size_of::<TraceSegment>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x2],
        };
        let depth = |write: bool, bias: wgpu::DepthBiasState| wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(write),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: wgpu::StencilState::default(),
            bias,
        };
        let opaque = [Some(wgpu::ColorTargetState {
            format: DRAW_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let blended = [Some(wgpu::ColorTargetState {
            format: DRAW_FORMAT,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let mesh_pipeline = |label: &str, fs: &str, cull: Option<wgpu::Face>| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&main_layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_mesh"),
                    compilation_options: Default::default(),
                    buffers: &[Some(vertex_layout.clone())],
                },
                primitive: wgpu::PrimitiveState { cull_mode: cull, ..Default::default() },
                depth_stencil: Some(depth(true, wgpu::DepthBiasState::default())),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &opaque,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let body_pipeline = mesh_pipeline("bodies", "fs_body", Some(wgpu::Face::Back));
        let table_pipeline = mesh_pipeline("table", "fs_table", None);
        // Traces lie on the table: drawn after it with a depth bias towards the eye, so they
        // win against the table at any distance yet still hide behind a body.
        let trace_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("traces"),
            layout: Some(&main_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_trace"),
                compilation_options: Default::default(),
                buffers: &[Some(trace_layout)],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(depth(
                false,
                wgpu::DepthBiasState { constant: -4, slope_scale: -2.0, clamp: 0.0 },
            )),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_trace"),
                compilation_options: Default::default(),
                targets: &blended,
            }),
            multiview_mask: None,
            cache: None,
        });
        // Shadow and contact shading of the table near the bodies: multiplies what the table
        // and the traces left (blend: source times destination), before the bodies are drawn.
        let multiply = [Some(wgpu::ColorTargetState {
            format: DRAW_FORMAT,
            blend: Some(wgpu::BlendState {
                color: wgpu::BlendComponent {
                    src_factor: wgpu::BlendFactor::Dst,
                    dst_factor: wgpu::BlendFactor::Zero,
                    operation: wgpu::BlendOperation::Add,
                },
                alpha: wgpu::BlendComponent {
                    src_factor: wgpu::BlendFactor::Zero,
                    dst_factor: wgpu::BlendFactor::One,
                    operation: wgpu::BlendOperation::Add,
                },
            }),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let shade_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("table shading"),
            layout: Some(&main_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_shade"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(depth(
                false,
                wgpu::DepthBiasState { constant: -4, slope_scale: -2.0, clamp: 0.0 },
            )),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_shade"),
                compilation_options: Default::default(),
                targets: &multiply,
            }),
            multiview_mask: None,
            cache: None,
        });
        let shadow_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadow"),
            layout: Some(&shadow_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_shadow"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout.clone())],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(depth(true, wgpu::DepthBiasState { constant: 2, slope_scale: 2.0, clamp: 0.0 })),
            multisample: wgpu::MultisampleState::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });

        let blit = output_format.map(|f| Blit::new(device, f));
        let mut r = SceneRenderer {
            body_pipeline,
            table_pipeline,
            trace_pipeline,
            shade_pipeline,
            shadow_pipeline,
            blit,
            globals_layout,
            objects_layout,
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
            layout: &self.globals_layout,
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
            layout: &self.objects_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &objects,
                    offset: 0,
                    size: NonZeroU64::new(96),
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

    /// Meshes for `geoms`, made when missing; returns their indices in `self.bodies`.
    fn ensure_meshes(&mut self, device: &wgpu::Device, geoms: &[BodyGeometry]) -> Vec<usize> {
        let keys: Vec<[u32; 3]> = geoms.iter().map(|g| g.key()).collect();
        // A slider dragging through sizes makes a new mesh per size: keep only a few, never
        // one this frame uses.
        if self.bodies.len() + keys.len() > 6 {
            self.bodies.retain(|(k, _)| keys.contains(k));
        }
        for g in geoms {
            if !self.bodies.iter().any(|(k, _)| *k == g.key()) {
                self.bodies.push((g.key(), GpuMesh::new(device, &mesh::body_mesh(g), "body")));
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
        let centre = frame.bodies.iter().map(|b| b.world_from_ring.w_axis.truncate()).sum::<Vec3>() / n;
        let centre = Vec3::new(centre.x, centre.y, 0.0);
        let reach = frame
            .bodies
            .iter()
            .map(|b| {
                let c = b.world_from_ring.w_axis.truncate();
                Vec3::new(c.x - centre.x, c.y - centre.y, 0.0).length() + b.geometry.r + b.geometry.h
            })
            .fold(scale, f32::max)
            * 1.4;
        let light_view = glam::camera::rh::view::look_at_mat4(centre + light * 4.0 * reach, centre, Vec3::Z);
        let light_proj = glam::camera::rh::proj::directx::orthographic(-reach, reach, -reach, reach, 0.01 * reach, 8.0 * reach);
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
            table: [frame.grid_spacing, fade_radius, 4.0 * scale, scale],
            fade_center: [
                frame.focus.x,
                frame.focus.y,
                2.0 * reach / SHADOW_SIZE as f32,
                2.0 * (0.5 * cam.fov_y).tan() / size[1] as f32,
            ],
            contacts,
            background: Vec3::from(BACKGROUND).extend(1.0).to_array(),
            shade_rect: shade_rect(&frame.bodies, light),
            table_srgb: {
                // As the table shader lit it: ambient plus the sun from its height.
                let lit = 0.45 + 0.6 * light.z;
                [srgb_encode(TABLE_COLOR[0] * lit), srgb_encode(TABLE_COLOR[1] * lit * 0.96), srgb_encode(TABLE_COLOR[2] * lit * 0.90), 1.0]
            },
            background_srgb: [srgb_encode(BACKGROUND[0]), srgb_encode(BACKGROUND[1]), srgb_encode(BACKGROUND[2]), 1.0],
        };
        queue.write_buffer(&self.slots[slot].globals, 0, bytemuck::bytes_of(&globals));

        // Object 0: the table, a square centred under the focus; then the bodies.
        let table_model = Mat4::from_translation(frame.focus.extend(0.0)) * Mat4::from_scale(Vec3::splat(fade_radius));
        let mut objects = vec![ObjectUniform {
            model: table_model.to_cols_array_2d(),
            color: Vec3::from(TABLE_COLOR).extend(1.0).to_array(),
            material: [0.0, 1.0, 0.0, 0.0],
            _pad: [0.0; 40],
        }];
        let drawn = &frame.bodies[..frame.bodies.len().min(MAX_OBJECTS - 1)];
        let geoms: Vec<BodyGeometry> = drawn.iter().map(|b| b.geometry).collect();
        let meshes = self.ensure_meshes(device, &geoms);
        for b in drawn {
            objects.push(ObjectUniform {
                model: b.world_from_ring.to_cols_array_2d(),
                color: Vec4::from((Vec3::from(b.color), 1.0)).to_array(),
                material: [0.85, 60.0, 0.6, 0.0],
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
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.shadow_pipeline);
            pass.set_bind_group(0, &view.globals_group, &[]);
            for (k, &m) in meshes.iter().enumerate() {
                let mesh = &self.bodies[m].1;
                pass.set_bind_group(1, &view.objects_group, &[(k as u64 + 1) as u32 * OBJECT_STRIDE as u32]);
                pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..mesh.count, 0, 0..1);
            }
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
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &view.globals_group, &[]);
        pass.set_bind_group(2, &self.textures_group, &[]);
        pass.set_pipeline(&self.table_pipeline);
        pass.set_bind_group(1, &view.objects_group, &[0]);
        pass.set_vertex_buffer(0, self.table.vertices.slice(..));
        pass.set_index_buffer(self.table.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.table.count, 0, 0..1);
        if trace_count > 0 {
            pass.set_pipeline(&self.trace_pipeline);
            pass.set_vertex_buffer(0, view.traces.slice(..));
            pass.draw(0..6, 0..trace_count);
        }
        if !meshes.is_empty() {
            pass.set_pipeline(&self.shade_pipeline);
            pass.draw(0..6, 0..1);
        }
        pass.set_pipeline(&self.body_pipeline);
        for (k, &m) in meshes.iter().enumerate() {
            let mesh = &self.bodies[m].1;
            pass.set_bind_group(1, &view.objects_group, &[(k as u64 + 1) as u32 * OBJECT_STRIDE as u32]);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.count, 0, 0..1);
        }
    }

    /// Draws view `slot`'s last frame into `pass` (egui's, whose viewport is the 3D view).
    pub fn paint(&self, slot: usize, pass: &mut wgpu::RenderPass<'_>) {
        let target = self.slots.get(slot).and_then(|s| s.target.as_ref());
        let (Some(blit), Some(group)) = (&self.blit, target.and_then(|t| t.blit_group.as_ref())) else {
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

impl Blit {
    fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Blit {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("blit.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/blit.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("blit"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("blit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("blit"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_full"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some(if format.is_srgb() { "fs_decode" } else { "fs_copy" }),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Blit { pipeline, layout }
    }

    fn group(&self, device: &wgpu::Device, view: &wgpu::TextureView) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("blit"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(view) }],
        })
    }
}
