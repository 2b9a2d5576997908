// The 3D scene: lit bodies, the table, the traces on it, and the shadow-map pass.
// World space: Z up, lengths in the case's units. Colours are computed linear and written
// sRGB-encoded into an Rgba8Unorm target (read back as PNG, or copied as they are into egui's
// non-sRGB target). Software rasterisers (lavapipe) pay for every instruction on every pixel
// of the table, so the table shader is kept lean.

struct Globals {
    view_proj: mat4x4<f32>,
    light_view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    // xyz: unit vector towards the light.
    light_dir: vec4<f32>,
    // x: grid spacing (0: no grid), y: fade radius, w: scale (outer radius R).
    table: vec4<f32>,
    // xy: centre of the fade, z: shadow-map texel in world units, w: size of a pixel in world
    // units at unit distance from the eye.
    fade_center: vec4<f32>,
    // xy: a contact point, z: radius of its contact shading, w: strength (0: none).
    contacts: array<vec4<f32>, 2>,
    background: vec4<f32>,
    // xy: centre of the square of table that gets shadow and contact shading, z: half side.
    shade_rect: vec4<f32>,
    // The sunlit table and the background, already sRGB-encoded (the table shader then
    // encodes one scalar per pixel instead of a colour).
    table_srgb: vec4<f32>,
    background_srgb: vec4<f32>,
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

const SKY: vec3<f32> = vec3<f32>(0.80, 0.86, 0.95);
const GROUND: vec3<f32> = vec3<f32>(0.42, 0.34, 0.27);
const SUN: vec3<f32> = vec3<f32>(1.0, 0.96, 0.90);

// Linear to sRGB without pow (three square roots; within about 0.3% of the exact curve):
// pow costs a software rasteriser more than the rest of the table shader.
fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    let s1 = sqrt(x);
    let s2 = sqrt(s1);
    let s3 = sqrt(s2);
    return clamp(0.662002687 * s1 + 0.684122060 * s2 - 0.323583601 * s3 - 0.0225411470 * x, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Fraction of sunlight reaching `p` (1 = lit).
fn sunlight(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let texel = g.fade_center.z;
    let q = g.light_view_proj * vec4<f32>(p + n * (1.5 * texel), 1.0);
    let uv = q.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5, 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || q.z > 1.0) {
        return 1.0;
    }
    return sunlight_taps(uv, q.z);
}

fn sunlight_taps(uv: vec2<f32>, qz: f32) -> f32 {
    // One comparison tap, filtered 2x2 by the sampler: soft enough at this map size, and a
    // software rasteriser pays for every extra tap on every shaded pixel.
    return textureSampleCompareLevel(shadow_map, shadow_sampler, uv, qz - 0.0015);
}

// Darkening of the table next to a contact point: the thin wedge of air under a tilted rim.
fn contact_shade(xy: vec2<f32>) -> f32 {
    var k = 1.0;
    for (var i = 0; i < 2; i = i + 1) {
        let c = g.contacts[i];
        let r = max(c.z, 1e-6);
        let d2 = dot(xy - c.xy, xy - c.xy) / (r * r);
        k = k * (1.0 - c.w / (1.0 + d2 * d2));
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
    // material.w: a yielding body's depth offset (0 for the others and the table).
    o.clip.z = o.clip.z + obj.material.w * o.clip.w;
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
    // Vertex colour: the body's paint; alpha 1 is bare metal, 0 a painted mark, -1 matte
    // paint without a highlight (a film's marks, which a highlight would wash out).
    let base = i.color.rgb * obj.color.rgb;
    let metal = obj.material.x * max(i.color.a, 0.0);
    let gloss = select(1.0, 0.0, i.color.a < -0.5);
    let lit = sunlight(i.world, n);
    let hemi = mix(GROUND, SKY, 0.5 + 0.5 * n.z);
    let diffuse = max(dot(n, l), 0.0) * lit;
    let r = reflect(-v, n);
    let env = mix(GROUND * 0.8, SKY * 1.1, smoothstep(-0.25, 0.55, r.z));
    // Schlick's rational stand-in for pow(x, shininess): no pow per pixel.
    let nh = max(dot(n, h), 0.0);
    let spec = nh / (obj.material.y - obj.material.y * nh + nh) * obj.material.z * lit;
    var c = base * (0.35 * hemi + 0.75 * diffuse * SUN) * (1.0 - metal);
    c = c + metal * base * (0.55 * env + 0.45 * diffuse * SUN);
    c = c + gloss * spec * SUN;
    return vec4<f32>(srgb_encode(c), 1.0);
}

@fragment
fn fs_table(i: MeshOut) -> @location(0) vec4<f32> {
    let xy = i.world.xy;
    // Grid: minor lines every spacing, major every five; minor ones fade out where they would
    // be closer than a few pixels.
    let q = xy / g.table.x;
    let fw = max(fwidth(q), vec2<f32>(1e-6));
    let minor = abs(fract(q - 0.5) - 0.5) / fw;
    let minor_line = (1.0 - clamp(min(minor.x, minor.y), 0.0, 1.0)) * (1.0 - smoothstep(0.15, 0.35, max(fw.x, fw.y)));
    let fw5 = fw * 0.2;
    let major = abs(fract(q * 0.2 - 0.5) - 0.5) / fw5;
    let major_line = (1.0 - clamp(min(major.x, major.y) * 0.6, 0.0, 1.0)) * (1.0 - smoothstep(0.2, 0.5, max(fw5.x, fw5.y)));
    // Darkening by the lines, applied to the encoded colour (encode(c k) ~ encode(c) encode(k));
    // a spacing of 0 is no grid (a film's table).
    let k = select(1.0, 1.0 - max(0.2 * minor_line, 0.38 * major_line), g.table.x > 0.0);
    let c = g.table_srgb.rgb * srgb_encode(vec3<f32>(k, 0.0, 0.0)).x;
    // Sunlit everywhere here; the shading pass darkens the shadow and the contacts.
    let f = smoothstep(0.55 * g.table.y, g.table.y, length(xy - g.fade_center.xy));
    return vec4<f32>(mix(c, g.background_srgb.rgb, f), 1.0);
}

// ---- shadow and contact shading of the table, one square around the bodies ----------------
// Drawn over the table and the traces with a multiplying blend, so that only the pixels near
// the bodies pay for the shadow-map look-ups.

struct ShadeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) xy: vec2<f32>,
    @location(1) light: vec3<f32>,
};

@vertex
fn vs_shade(@builtin(vertex_index) vi: u32) -> ShadeOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let xy = g.shade_rect.xy + corners[vi] * g.shade_rect.z;
    let w = vec4<f32>(xy, 0.0, 1.0);
    var o: ShadeOut;
    o.clip = g.view_proj * w;
    o.xy = xy;
    // The table is a plane: its light-space position is affine, so it interpolates exactly.
    let q = g.light_view_proj * w;
    o.light = vec3<f32>(q.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5, 0.5), q.z);
    return o;
}

@fragment
fn fs_shade(i: ShadeOut) -> @location(0) vec4<f32> {
    var lit = 1.0;
    if (all(i.light.xy > vec2<f32>(0.0)) && all(i.light.xy < vec2<f32>(1.0))) {
        lit = sunlight_taps(i.light.xy, i.light.z);
    }
    let k = (0.45 + 0.6 * g.light_dir.z * lit) / (0.45 + 0.6 * g.light_dir.z) * contact_shade(i.xy);
    // The target holds sRGB-encoded values: scale them by the encoded factor (one channel's
    // worth of encoding, not three).
    let e = srgb_encode(vec3<f32>(k, 0.0, 0.0)).x;
    return vec4<f32>(e, e, e, 1.0);
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
    // x: half width, y: least half width in pixels.
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
    // Never thinner than a few pixels, so that far paths stay visible.
    let mid = vec3<f32>(mix(a, b, k.x), 0.0);
    let hw = max(s.extra.x, s.extra.y * g.fade_center.w * distance(mid, g.eye.xyz));
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
    o.world = vec3<f32>(p, 0.0);
    o.clip = g.view_proj * vec4<f32>(o.world, 1.0);
    o.color = s.color;
    o.across = k.y;
    return o;
}

@fragment
fn fs_trace(i: SegOut) -> @location(0) vec4<f32> {
    // Coverage from the distance to the edge in pixels: full inside, half on the edge.
    let e = abs(i.across);
    let per_px = max(fwidth(i.across), 1e-4);
    let alpha = i.color.a * clamp((1.0 - e) / per_px + 0.5, 0.0, 1.0);
    let c = fade(i.world.xy, i.color.rgb * (0.55 + 0.5 * g.light_dir.z));
    return vec4<f32>(srgb_encode(c), alpha);
}
