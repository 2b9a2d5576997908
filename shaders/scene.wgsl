// The 3D scene: lit bodies, the table, the traces on it, and the shadow-map pass.
// World space: Z up, lengths in the case's units. Output is sRGB-encoded (the offscreen
// target is Rgba8Unorm, read back as PNG or copied into egui's non-sRGB target).

struct Globals {
    view_proj: mat4x4<f32>,
    light_view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    // xyz: unit vector towards the light.
    light_dir: vec4<f32>,
    // x: grid spacing, y: fade radius, z: texture tile size, w: scale (outer radius R).
    table: vec4<f32>,
    // xy: centre of the fade, z: shadow-map texel in world units.
    fade_center: vec4<f32>,
    // xy: a contact point, z: radius of its contact shading, w: strength (0: none).
    contacts: array<vec4<f32>, 2>,
    background: vec4<f32>,
};

struct Object {
    model: mat4x4<f32>,
    color: vec4<f32>,
    // x: metallic, y: shininess, z: specular strength.
    material: vec4<f32>,
};

@group(0) @binding(0) var<uniform> g: Globals;
@group(1) @binding(0) var<uniform> obj: Object;
@group(2) @binding(0) var shadow_map: texture_depth_2d;
@group(2) @binding(1) var shadow_sampler: sampler_comparison;
@group(2) @binding(2) var table_tex: texture_2d<f32>;
@group(2) @binding(3) var table_sampler: sampler;

const SKY: vec3<f32> = vec3<f32>(0.80, 0.86, 0.95);
const GROUND: vec3<f32> = vec3<f32>(0.42, 0.34, 0.27);
const SUN: vec3<f32> = vec3<f32>(1.0, 0.96, 0.90);

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    let lo = x * 12.92;
    let hi = 1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, x <= vec3<f32>(0.0031308));
}

// Fraction of sunlight reaching `p` (1 = lit), four taps of the comparison sampler (each a
// bilinear 2x2 filter) for a soft edge.
fn sunlight(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let texel = g.fade_center.z;
    let q = g.light_view_proj * vec4<f32>(p + n * (1.5 * texel), 1.0);
    let uv = q.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5, 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || q.z > 1.0) {
        return 1.0;
    }
    let d = 1.0 / vec2<f32>(textureDimensions(shadow_map));
    let z = q.z - 0.0015;
    var s = 0.0;
    s += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(-0.7, -0.3) * d, z);
    s += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(0.3, -0.7) * d, z);
    s += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(0.7, 0.3) * d, z);
    s += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(-0.3, 0.7) * d, z);
    return s * 0.25;
}

// Darkening of the table next to a contact point: the thin wedge of air under a tilted rim.
fn contact_shade(xy: vec2<f32>) -> f32 {
    var k = 1.0;
    for (var i = 0; i < 2; i = i + 1) {
        let c = g.contacts[i];
        let r = max(c.z, 1e-6);
        let d2 = dot(xy - c.xy, xy - c.xy) / (r * r);
        k = k * (1.0 - c.w * exp(-d2));
    }
    return k;
}

fn fade(xy: vec2<f32>, c: vec3<f32>) -> vec3<f32> {
    let d = length(xy - g.fade_center.xy);
    let f = smoothstep(0.55 * g.table.y, g.table.y, d);
    return mix(c, g.background.rgb, f);
}

// ---- bodies -------------------------------------------------------------------------------

struct MeshIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_mesh(v: MeshIn) -> MeshOut {
    var o: MeshOut;
    let w = obj.model * vec4<f32>(v.pos, 1.0);
    o.world = w.xyz;
    o.clip = g.view_proj * w;
    o.normal = (obj.model * vec4<f32>(v.normal, 0.0)).xyz;
    o.color = v.color;
    return o;
}

@fragment
fn fs_body(i: MeshOut) -> @location(0) vec4<f32> {
    let n = normalize(i.normal);
    let l = g.light_dir.xyz;
    let v = normalize(g.eye.xyz - i.world);
    let h = normalize(l + v);
    // Vertex colour: the body's paint; alpha 1 is bare metal, 0 a painted mark.
    let base = i.color.rgb * obj.color.rgb;
    let metal = obj.material.x * i.color.a;
    let lit = sunlight(i.world, n);
    let hemi = mix(GROUND, SKY, 0.5 + 0.5 * n.z);
    let diffuse = max(dot(n, l), 0.0) * lit;
    let r = reflect(-v, n);
    let env = mix(GROUND * 0.8, SKY * 1.1, smoothstep(-0.25, 0.55, r.z));
    let spec = pow(max(dot(n, h), 0.0), obj.material.y) * obj.material.z * lit;
    var c = base * (0.35 * hemi + 0.75 * diffuse * SUN) * (1.0 - metal);
    c = c + metal * base * (0.55 * env + 0.45 * diffuse * SUN);
    c = c + spec * SUN;
    return vec4<f32>(srgb_encode(c), 1.0);
}

@fragment
fn fs_table(i: MeshOut) -> @location(0) vec4<f32> {
    let xy = i.world.xy;
    let grain = textureSample(table_tex, table_sampler, xy / g.table.z).r;
    var base = obj.color.rgb * (0.82 + 0.36 * grain);
    // Grid: minor lines every spacing, major every five; minor ones fade out where they would
    // be closer than a few pixels.
    let s = g.table.x;
    let q = xy / s;
    let fw = max(fwidth(q), vec2<f32>(1e-6));
    let minor = abs(fract(q - 0.5) - 0.5) / fw;
    let minor_line = (1.0 - clamp(min(minor.x, minor.y), 0.0, 1.0)) * (1.0 - smoothstep(0.15, 0.35, max(fw.x, fw.y)));
    let q5 = q / 5.0;
    let fw5 = fw / 5.0;
    let major = abs(fract(q5 - 0.5) - 0.5) / fw5;
    let major_line = (1.0 - clamp(min(major.x, major.y) / 1.6, 0.0, 1.0)) * (1.0 - smoothstep(0.2, 0.5, max(fw5.x, fw5.y)));
    base = mix(base, base * 0.62, max(0.45 * minor_line, 0.8 * major_line));
    let lit = sunlight(i.world, vec3<f32>(0.0, 0.0, 1.0));
    let shade = (0.45 + 0.6 * g.light_dir.z * lit) * contact_shade(xy);
    let c = fade(xy, base * shade * SUN);
    return vec4<f32>(srgb_encode(c), 1.0);
}

// ---- shadow map -----------------------------------------------------------------------------

@vertex
fn vs_shadow(v: MeshIn) -> @builtin(position) vec4<f32> {
    return g.light_view_proj * obj.model * vec4<f32>(v.pos, 1.0);
}

// ---- traces: segments on the table, one instance each -------------------------------------

struct SegIn {
    @location(0) ab: vec4<f32>,
    @location(1) color: vec4<f32>,
    // x: half width, y: height above the table.
    @location(2) extra: vec2<f32>,
};

struct SegOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) across: f32,
};

@vertex
fn vs_trace(@builtin(vertex_index) vi: u32, s: SegIn) -> SegOut {
    // Two triangles: corners (along, across) in {0,1} x {-1,1}, extended by a half width at
    // both ends so that consecutive segments overlap at the joints.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    let k = corners[vi];
    let a = s.ab.xy;
    let b = s.ab.zw;
    let hw = s.extra.x;
    var dir = b - a;
    let len = length(dir);
    if (len > 1e-9) {
        dir = dir / len;
    } else {
        dir = vec2<f32>(1.0, 0.0);
    }
    let side = vec2<f32>(-dir.y, dir.x);
    let p = mix(a, b, k.x) + dir * (2.0 * k.x - 1.0) * hw + side * k.y * hw;
    var o: SegOut;
    o.world = vec3<f32>(p, s.extra.y);
    o.clip = g.view_proj * vec4<f32>(o.world, 1.0);
    o.color = s.color;
    o.across = k.y;
    return o;
}

@fragment
fn fs_trace(i: SegOut) -> @location(0) vec4<f32> {
    let e = abs(i.across);
    let aa = max(fwidth(i.across), 1e-4);
    let alpha = i.color.a * (1.0 - smoothstep(1.0 - 1.5 * aa, 1.0, e));
    let lit = sunlight(i.world, vec3<f32>(0.0, 0.0, 1.0));
    let shade = 0.55 + 0.5 * g.light_dir.z * lit;
    let c = fade(i.world.xy, i.color.rgb * shade);
    return vec4<f32>(srgb_encode(c), alpha);
}
