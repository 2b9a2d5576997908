// egui's own triangles (text, widgets, plots), drawn by ringlab on a software rasteriser.
// egui-wgpu's shader chooses between hardware and hand-made texture filtering and dithering
// by uniform flags; lavapipe runs both sides of every such branch on every pixel, which made
// egui most of the window's frame. This one does only what the window needs: vertex colour
// times the font atlas, with a separate entry point per kind of target instead of a branch.

struct Screen {
    // The window in egui points (vertex positions are in points).
    size_points: vec2<f32>,
    _pad: vec2<f32>,
};

@group(0) @binding(0) var<uniform> screen: Screen;
@group(0) @binding(1) var atlas: texture_2d<f32>;
@group(0) @binding(2) var atlas_sampler: sampler;

struct VertexIn {
    @location(0) pos: vec2<f32>,
    @location(1) uv: vec2<f32>,
    // egui's Color32: premultiplied, sRGB-encoded, bytes r, g, b, a.
    @location(2) color: u32,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) color: vec4<f32>,
};

@vertex
fn vs_ui(v: VertexIn) -> VertexOut {
    var o: VertexOut;
    o.clip = vec4<f32>(2.0 * v.pos.x / screen.size_points.x - 1.0, 1.0 - 2.0 * v.pos.y / screen.size_points.y, 0.0, 1.0);
    o.uv = v.uv;
    o.color = unpack4x8unorm(v.color);
    return o;
}

// A non-sRGB target (what egui-wgpu prefers): the encoded values go through as they are.
@fragment
fn fs_ui(i: VertexOut) -> @location(0) vec4<f32> {
    return i.color * textureSample(atlas, atlas_sampler, i.uv);
}

// An sRGB target: decode, and the target encodes again.
@fragment
fn fs_ui_srgb(i: VertexOut) -> @location(0) vec4<f32> {
    let c = i.color * textureSample(atlas, atlas_sampler, i.uv);
    let lo = c.rgb / 12.92;
    let hi = pow((c.rgb + 0.055) / 1.055, vec3<f32>(2.4));
    return vec4<f32>(select(hi, lo, c.rgb <= vec3<f32>(0.04045)), c.a);
}
