// Space Foosball scene shaders: background, lit instanced meshes, soft sprites, 2-D overlay.

struct Globals {
    view_proj: mat4x4<f32>,
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    eye: vec4<f32>,
    light_dir: vec4<f32>,
    // width, height (pixels), time (s), nebula downscale factor
    screen: vec4<f32>,
    // The star layers' grids of cells drawn (see `vs_star`): columns and rows per layer.
    star_cols: vec4<f32>,
    star_rows: vec4<f32>,
};

@group(0) @binding(0) var<uniform> g: Globals;

// ---------------------------------------------------------------- background

// A triangle covering the screen at the far plane (depth 1).
@vertex
fn vs_bg(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u);
    let y = f32(i & 2u);
    return vec4<f32>(x * 2.0 - 1.0, y * 2.0 - 1.0, 1.0, 1.0);
}

fn hash2(p: vec2<f32>) -> f32 {
    let q = fract(p * vec2<f32>(0.1031, 0.1030));
    let r = q + dot(q, q.yx + 33.33);
    return fract((r.x + r.y) * r.x);
}

fn noise(p: vec2<f32>) -> f32 {
    let i = floor(p);
    let f = fract(p);
    let u = f * f * (3.0 - 2.0 * f);
    let a = hash2(i);
    let b = hash2(i + vec2<f32>(1.0, 0.0));
    let c = hash2(i + vec2<f32>(0.0, 1.0));
    let d = hash2(i + vec2<f32>(1.0, 1.0));
    return mix(mix(a, b, u.x), mix(c, d, u.x), u.y);
}

fn fbm(p: vec2<f32>) -> f32 {
    var s = 0.0;
    var amp = 0.5;
    var q = p;
    for (var k = 0; k < 5; k = k + 1) {
        s = s + amp * noise(q);
        q = q * 2.03 + vec2<f32>(17.1, 9.2);
        amp = amp * 0.5;
    }
    return s;
}

// Resolution-independent sky coordinates of a full-size pixel: 720 units per screen
// height.
fn sky_coords(px: vec2<f32>) -> vec2<f32> {
    return px / g.screen.y * 720.0;
}

// Nebula: two drifting fbm layers in violet and teal over the dark sky (linear RGB).
// Drawn into a texture of a quarter of the screen's width and height (`screen.w` is
// that factor): the nebula has no detail finer than a few pixels, and this is most of
// the background's arithmetic.
@fragment
fn fs_nebula(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let t = g.screen.z;
    let p = sky_coords(frag.xy * g.screen.w);
    let n1 = fbm(p * 0.004 + vec2<f32>(t * 0.012, 0.0));
    let n2 = fbm(p * 0.007 - vec2<f32>(0.0, t * 0.008) + vec2<f32>(n1 * 1.5, 3.7));
    var col = vec3<f32>(0.004, 0.004, 0.016);
    col = col + vec3<f32>(0.16, 0.03, 0.22) * smoothstep(0.45, 0.85, n1);
    col = col + vec3<f32>(0.0, 0.10, 0.16) * smoothstep(0.5, 0.9, n2);
    return vec4<f32>(col, 1.0);
}

@group(1) @binding(0) var nebula_tex: texture_2d<f32>;
@group(1) @binding(1) var nebula_sampler: sampler;

// The nebula texture filtered up to full size. Drawn after the opaque meshes at the
// far plane, so the depth test leaves out every pixel the table covers.
@fragment
fn fs_sky(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let col = textureSampleLevel(nebula_tex, nebula_sampler, frag.xy / g.screen.xy, 0.0).rgb;
    return vec4<f32>(col, 1.0);
}

// Stars: three parallax layers of jittered grid cells in sky coordinates, drifting left
// at 3, 8 and 13 units/s; a cell holds a star when its hash is over 0.55. Each cell of
// the grid over the screen is one instance: a small quad at the far plane (degenerate
// for an empty cell), so the stars cost a few fragments each instead of arithmetic on
// every sky pixel.
struct StarOut {
    @builtin(position) clip: vec4<f32>,
    // Offset from the star's centre, sky units.
    @location(0) offset: vec2<f32>,
    @location(1) color: vec3<f32>,
    @location(2) falloff: f32,
};

// Half size of a star's quad, sky units: the dimmest layer's glow is under 1/255 there.
const STAR_RADIUS: f32 = 3.5;

@vertex
fn vs_star(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> StarOut {
    var o: StarOut;
    // Which layer and cell this instance is.
    var k = 0u;
    var local = f32(ii);
    if (local >= g.star_cols.x * g.star_rows.x) {
        local = local - g.star_cols.x * g.star_rows.x;
        k = 1u;
        if (local >= g.star_cols.y * g.star_rows.y) {
            local = local - g.star_cols.y * g.star_rows.y;
            k = 2u;
        }
    }
    let fk = f32(k);
    let cols = g.star_cols[k];
    let cell = 46.0 - 14.0 * fk;
    let t = g.screen.z;
    let shift = t * (3.0 + 5.0 * fk);
    let row = floor(local / cols);
    let col = local - row * cols;
    // One cell beyond each edge: a star's glow reaches past its cell.
    let id = vec2<f32>(floor(shift / cell) + col - 1.0, row - 1.0);
    let r = hash2(id + vec2<f32>(fk * 31.0, fk * 17.0));
    let off = vec2<f32>(hash2(id + 7.3), hash2(id + 3.1)) * 0.8 + 0.1;
    let centre = (id + off) * cell - vec2<f32>(shift, 0.0);
    let c = quad_corner(vi) * STAR_RADIUS;
    let px = (centre + c) * g.screen.y / 720.0;
    var clip = vec4<f32>(px.x / g.screen.x * 2.0 - 1.0, 1.0 - px.y / g.screen.y * 2.0, 1.0, 1.0);
    if (r <= 0.55) {
        clip = vec4<f32>(2.0, 2.0, 1.0, 1.0);
    }
    let tw = 0.65 + 0.35 * sin(t * (1.5 + 4.0 * r) + r * 60.0);
    let tint = mix(vec3<f32>(0.7, 0.8, 1.0), vec3<f32>(1.0, 0.9, 0.8), hash2(id + 1.7));
    o.clip = clip;
    o.offset = c;
    o.color = tint * tw * (1.4 - fk * 0.35);
    o.falloff = 0.9 - 0.2 * fk;
    return o;
}

// Additive: the star's gaussian glow over the sky.
@fragment
fn fs_star(i: StarOut) -> @location(0) vec4<f32> {
    let b = exp(-dot(i.offset, i.offset) * i.falloff);
    return vec4<f32>(i.color * b, 0.0);
}

// ---------------------------------------------------------------- lit meshes

struct MeshIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) center: vec4<f32>,
    @location(3) half: vec4<f32>,
    @location(4) rot: vec4<f32>,
    @location(5) color: vec4<f32>,
};

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) emissive: f32,
};

fn qrot(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

@vertex
fn vs_mesh(m: MeshIn) -> MeshOut {
    var o: MeshOut;
    let world = m.center.xyz + qrot(m.rot, m.pos * m.half.xyz);
    o.clip = g.view_proj * vec4<f32>(world, 1.0);
    o.world = world;
    o.normal = qrot(m.rot, m.normal / max(m.half.xyz, vec3<f32>(1e-6)));
    o.color = m.color;
    o.emissive = m.center.w;
    return o;
}

@fragment
fn fs_mesh(i: MeshOut) -> @location(0) vec4<f32> {
    // Cheap on a software rasteriser: `light_dir` is normalised on the CPU, and the
    // powers are products (x^32 by five squarings) rather than exp/log.
    let n = normalize(i.normal);
    let l = g.light_dir.xyz;
    let v = normalize(g.eye.xyz - i.world);
    let diff = max(dot(n, l), 0.0);
    let s1 = max(dot(reflect(-l, n), v), 0.0);
    let s2 = s1 * s1;
    let s4 = s2 * s2;
    let s8 = s4 * s4;
    let s16 = s8 * s8;
    let spec = s16 * s16 * 0.35;
    let e = 1.0 - max(dot(n, v), 0.0);
    let rim = e * e * e * 0.25;
    let base = i.color.rgb;
    let col = base * (0.3 + 0.7 * diff) + vec3<f32>(spec) + rim * vec3<f32>(0.3, 0.5, 1.0)
        + base * i.emissive;
    return vec4<f32>(col, 1.0);
}

// ---------------------------------------------------------------- sprites

struct SpriteIn {
    @location(0) center: vec4<f32>,
    @location(1) size: vec4<f32>,
    @location(2) color: vec4<f32>,
};

struct SpriteOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) corner: vec2<f32>,
    @location(1) color: vec4<f32>,
    @location(2) hardness: f32,
};

fn quad_corner(i: u32) -> vec2<f32> {
    var c = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0));
    return c[i];
}

@vertex
fn vs_sprite(@builtin(vertex_index) vi: u32, s: SpriteIn) -> SpriteOut {
    let c = quad_corner(vi);
    var world: vec3<f32>;
    if (s.center.w < 0.5) {
        world = s.center.xyz + (g.cam_right.xyz * c.x + g.cam_up.xyz * c.y) * s.size.x;
    } else {
        world = s.center.xyz + vec3<f32>(c.x, c.y, 0.0) * s.size.x;
    }
    var o: SpriteOut;
    o.clip = g.view_proj * vec4<f32>(world, 1.0);
    o.corner = c;
    o.color = s.color;
    o.hardness = s.size.y;
    return o;
}

// Premultiplied output: blended with (One, OneMinusSrcAlpha) for shadows and
// (One, One) for glowing particles.
@fragment
fn fs_sprite(i: SpriteOut) -> @location(0) vec4<f32> {
    let d = length(i.corner);
    let a = i.color.a * pow(clamp(1.0 - d, 0.0, 1.0), i.hardness);
    let core = smoothstep(0.35, 0.0, d);
    return vec4<f32>(i.color.rgb * a * (1.0 + 2.0 * core), a);
}

// ---------------------------------------------------------------- overlay

struct UiIn {
    @location(0) rect: vec4<f32>,
    @location(1) color: vec4<f32>,
};

struct UiOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_ui(@builtin(vertex_index) vi: u32, u: UiIn) -> UiOut {
    let c = quad_corner(vi) * 0.5 + 0.5;
    let px = mix(u.rect.xy, u.rect.zw, c);
    var o: UiOut;
    o.clip = vec4<f32>(px.x / g.screen.x * 2.0 - 1.0, 1.0 - px.y / g.screen.y * 2.0, 0.0, 1.0);
    o.color = u.color;
    return o;
}

@fragment
fn fs_ui(i: UiOut) -> @location(0) vec4<f32> {
    return vec4<f32>(i.color.rgb * i.color.a, i.color.a);
}
