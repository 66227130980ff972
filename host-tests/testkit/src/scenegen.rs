//! A seeded generator of random but valid scenes: what a new user might write.
//!
//! Each seed gives one scene file's text, the same on every machine. Scenes
//! cover the whole format: every shape, every keyword (the photographer's
//! camera statements included), named materials and explicit reflectances,
//! transformation lines in any order with or without a `total_transformation`
//! count, checker textures, up to eight lights, shadows, pinhole and thin-lens
//! cameras, cameras anywhere within ±60 looking any way (level or tilted),
//! objects near (depth 1) and far (depth 1000), tiny (0.05) and huge (50), a
//! floor or walls in most scenes, comments, tabs and the other number spellings
//! the grammar allows. Every scene keeps to SPEC's range rules, so it parses.
//!
//! Objects are placed where the camera sees them (inside its field of view),
//! so that a scene's pixels say something about the renderer.
//!
//! ```
//! use lensray_testkit::scenegen::{generate, generate_lens, generate_with, Options, Camera};
//! let text = generate(7);
//! assert_eq!(text, generate(7), "the same seed gives the same scene");
//! assert!(lensray::Scene::<f32>::parse(&text).is_ok());
//! let lens = generate_lens(7);
//! assert!(lensray::Scene::<f32>::parse(&lens).unwrap().camera.radius > 0.0);
//! let pinhole = generate_with(7, &Options { camera: Camera::Pinhole, ..Options::default() });
//! assert_eq!(lensray::Scene::<f32>::parse(&pinhole).unwrap().camera.radius, 0.0);
//! ```

use std::fmt::Write;

/// Which cameras a generated scene may have.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Camera {
    /// A pinhole or a thin lens, by the seed (about a third lenses).
    Any,
    /// Pinhole cameras only (`radius 0`).
    Pinhole,
    /// Thin-lens cameras only (a radius above 0, by `radius` or `f_number`).
    Lens,
}

/// What [`generate_with`] makes.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Options {
    /// Pinhole, lens, or either.
    pub camera: Camera,
    /// Most objects a scene gets (1 to 16).
    pub max_objects: usize,
    /// Most lights a scene gets (1 to 8).
    pub max_lights: usize,
}

impl Default for Options {
    /// Any camera, up to 16 objects and 8 lights.
    fn default() -> Self {
        Options {
            camera: Camera::Any,
            max_objects: lensray::MAX_OBJECTS,
            max_lights: lensray::MAX_LIGHTS,
        }
    }
}

/// The scene of `seed`, with any camera.
pub fn generate(seed: u64) -> String {
    generate_with(seed, &Options::default())
}

/// The scene of `seed` with a thin-lens camera (`radius > 0`).
pub fn generate_lens(seed: u64) -> String {
    generate_with(
        seed,
        &Options {
            camera: Camera::Lens,
            ..Options::default()
        },
    )
}

/// The scene of `seed` under `options`. The same seed and options give the
/// same text; a different [`Camera`] choice gives a different scene.
pub fn generate_with(seed: u64, options: &Options) -> String {
    let salt = match options.camera {
        Camera::Any => 0,
        Camera::Pinhole => 0x5049_4e48,
        Camera::Lens => 0x4c45_4e53,
    };
    Gen {
        rng: Rng::new(seed ^ salt),
        out: String::new(),
        options: *options,
        tabs: false,
        plain: true,
    }
    .scene()
}

/// splitmix64: small and the same everywhere.
#[derive(Clone, Debug)]
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        // Mixed first, so that neighbouring seeds start far apart.
        let mut r = Rng(seed.wrapping_mul(0xD1B5_4A32_D192_ED03));
        r.next_u64();
        r
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Log-uniform in [lo, hi) (both > 0): as many small as large.
    fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }

    /// Uniform in `lo..=hi`.
    fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }

    /// True with probability `p`.
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.int(0, items.len() - 1)]
    }

    /// A uniformly random unit vector.
    fn direction(&mut self) -> [f64; 3] {
        loop {
            let v = [self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0)];
            let l = norm(v);
            if l > 0.1 && l <= 1.0 {
                return v.map(|x| x / l);
            }
        }
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = norm(v);
    v.map(|x| x / l)
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scaled(a: [f64; 3], s: f64) -> [f64; 3] {
    a.map(|x| x * s)
}

/// The camera as the generator placed it (world space), for placing objects.
struct View {
    eye: [f64; 3],
    /// Unit viewing direction, right and up of the picture.
    fwd: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    /// Half the field of view as a slope: film half-width over N, and half-height over N.
    half_w: f64,
    half_h: f64,
}

impl View {
    /// A point at `depth` along the view, at (`x`, `y`) in [-1, 1] of the field of view.
    fn at(&self, depth: f64, x: f64, y: f64) -> [f64; 3] {
        let lateral = add(
            scaled(self.right, x * self.half_w * depth),
            scaled(self.up, y * self.half_h * depth),
        );
        add(self.eye, add(scaled(self.fwd, depth), lateral))
    }
}

/// A transformation line, for composing the object's matrix as the parser does.
#[derive(Copy, Clone, Debug)]
enum Op {
    Scale([f64; 3]),
    Rotate(usize, f64),
    Translate([f64; 3]),
}

impl Op {
    /// The op applied to a point.
    fn apply(self, p: [f64; 3]) -> [f64; 3] {
        match self {
            Op::Scale(s) => [p[0] * s[0], p[1] * s[1], p[2] * s[2]],
            Op::Translate(t) => add(p, t),
            Op::Rotate(axis, deg) => {
                let (s, c) = deg.to_radians().sin_cos();
                let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
                let mut q = p;
                q[i] = c * p[i] - s * p[j];
                q[j] = s * p[i] + c * p[j];
                q
            }
        }
    }

    /// The inverse op applied to a point.
    fn unapply(self, p: [f64; 3]) -> [f64; 3] {
        match self {
            Op::Scale(s) => [p[0] / s[0], p[1] / s[1], p[2] / s[2]],
            Op::Translate(t) => [p[0] - t[0], p[1] - t[1], p[2] - t[2]],
            Op::Rotate(axis, deg) => Op::Rotate(axis, -deg).apply(p),
        }
    }

    /// How much the op can stretch a length, at most.
    fn stretch(self) -> f64 {
        match self {
            Op::Scale(s) => s.iter().fold(0.0f64, |m, x| m.max(x.abs())),
            _ => 1.0,
        }
    }
}

/// Named materials of the format.
const MATERIALS: [&str; 12] = [
    "gold", "copper", "silver", "brass", "bronze", "chrome", "pewter", "emerald", "jade", "ruby", "pearl", "obsidian",
];
const SHAPES: [&str; 5] = ["sphere", "plane", "cube", "cylinder", "cone"];

struct Gen {
    rng: Rng,
    out: String,
    options: Options,
    /// Separate values with tabs in this scene.
    tabs: bool,
    /// Write numbers plainly (else sometimes `.5`, `+2`, `1.`).
    plain: bool,
}

impl Gen {
    /// A real as the format spells it, rounded to 4 decimals, below 32768.
    fn num(&mut self, x: f64) -> String {
        let x = x.clamp(-32767.0, 32767.0);
        let mut s = format!("{:.4}", x);
        // Trailing zeros off: "2.5000" is "2.5", "3.0000" is "3".
        while s.contains('.') && s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
        if s == "-0" {
            s = "0".into();
        }
        if !self.plain {
            match self.rng.int(0, 5) {
                0 if s.starts_with("0.") => s = s[1..].to_string(),
                1 if s.starts_with("-0.") => s = format!("-{}", &s[2..]),
                2 if !s.starts_with('-') => s = format!("+{s}"),
                3 if !s.contains('.') => s.push('.'),
                _ => {}
            }
        }
        s
    }

    /// The value a number parses to: what the renderer will see.
    fn exact(&mut self, x: f64) -> f64 {
        let s = self.num(x);
        s.parse::<f64>().unwrap_or(0.0)
    }

    /// Uniform in [lo, hi), as written.
    fn exact_range(&mut self, lo: f64, hi: f64) -> f64 {
        let x = self.rng.range(lo, hi);
        self.exact(x)
    }

    /// Log-uniform in [lo, hi), as written.
    fn exact_log_range(&mut self, lo: f64, hi: f64) -> f64 {
        let x = self.rng.log_range(lo, hi);
        self.exact(x)
    }

    /// Writes a statement: keyword and values, separated by a space or a tab.
    fn line(&mut self, keyword: &str, values: &[String]) {
        let sep = if self.tabs && self.rng.chance(0.5) { "\t" } else { " " };
        self.out.push_str(keyword);
        for v in values {
            self.out.push_str(sep);
            self.out.push_str(v);
        }
        if self.rng.chance(0.03) {
            self.out.push_str("  # a comment, ünïcödé too");
        }
        self.out.push('\n');
    }

    fn triple(&mut self, keyword: &str, v: [f64; 3]) {
        let vals = [self.num(v[0]), self.num(v[1]), self.num(v[2])];
        self.line(keyword, &vals);
    }

    fn single(&mut self, keyword: &str, x: f64) {
        let v = self.num(x);
        self.line(keyword, &[v]);
    }

    fn colour(&mut self, lo: f64, hi: f64) -> [f64; 3] {
        let grey = self.rng.chance(0.3);
        let g = self.rng.range(lo, hi);
        [0; 3].map(|_| if grey { g } else { self.rng.range(lo, hi) })
    }

    fn scene(mut self) -> String {
        let rng = &mut self.rng;
        self.tabs = rng.chance(0.15);
        self.plain = rng.chance(0.8);
        let _ = writeln!(self.out, "# generated scene (lensray_testkit::scenegen)");
        if self.rng.chance(0.1) {
            // An early camera statement a later one overrides: the last one stands.
            self.single("width", 99.0);
        }
        let view = self.camera_position();
        let n_objects = self
            .rng
            .int(3.min(self.options.max_objects), 8.min(self.options.max_objects));
        let n_objects = if self.rng.chance(0.1) {
            self.rng.int(n_objects, self.options.max_objects.max(n_objects))
        } else {
            n_objects
        };
        let n_lights = if self.rng.chance(0.1) {
            self.rng.int(1, self.options.max_lights)
        } else {
            self.rng.int(1, 4.min(self.options.max_lights))
        };
        // Lights first, or interleaved with the objects (they may stand anywhere).
        let lights_between = self.rng.chance(0.3);
        if !lights_between {
            for _ in 0..n_lights {
                self.light(&view);
            }
        }
        if self.rng.chance(0.5) {
            self.line("shadows", &["on".into()]);
        } else if self.rng.chance(0.3) {
            self.line("shadows", &["off".into()]);
        }
        if self.rng.chance(0.3) {
            let bg = self.colour(0.0, 1.0);
            self.triple("background", bg);
        }
        let floor = self.rng.chance(0.75);
        let mut bounded = Vec::new();
        let mut lights_left = if lights_between { n_lights } else { 0 };
        for i in 0..n_objects {
            let shape = if (i == 0 && floor) || self.rng.chance(0.08) {
                "plane"
            } else {
                *self.rng.pick(&SHAPES[..])
            };
            if shape != "plane" {
                bounded.push(i + 1);
            }
            self.object(shape, &view, i == 0 && floor);
            if lights_left > 0 && self.rng.chance(0.5) {
                self.light(&view);
                lights_left -= 1;
            }
        }
        for _ in 0..lights_left {
            self.light(&view);
        }
        self.lens(&bounded);
        self.out
    }

    /// Writes the camera's position and framing; returns the view.
    fn camera_position(&mut self) -> View {
        let eye = if self.rng.chance(0.2) {
            [0.0; 3]
        } else {
            [0; 3].map(|_| self.rng.range(-60.0, 60.0))
        };
        // Level (looking along the ground, slightly up or down) or any way.
        let look = if self.rng.chance(0.5) {
            let yaw = self.rng.range(0.0, std::f64::consts::TAU);
            let pitch = self.rng.range(-0.3, 0.3);
            [yaw.cos() * pitch.cos(), pitch.sin(), yaw.sin() * pitch.cos()]
        } else if self.rng.chance(0.2) {
            [0.0, 0.0, -1.0]
        } else {
            self.rng.direction()
        };
        // Up: straight, or tilted (a rolled camera); never parallel to look.
        let up = loop {
            let up = if self.rng.chance(0.6) {
                [0.0, 1.0, 0.0]
            } else {
                unit(add(
                    [0.0, 1.0, 0.0],
                    scaled(self.rng.direction(), self.rng.range(0.1, 1.5)),
                ))
            };
            if norm(cross(up, look)) > 0.2 {
                break up;
            }
            if norm(cross([0.0, 1.0, 0.0], look)) < 0.2 {
                break [1.0, 0.0, 0.0];
            }
        };
        // Film width and image distance: wide angle to long telephoto.
        let big_n = self.rng.log_range(2.0, 40.0);
        let fov = self.rng.log_range(0.15, 2.5);
        let aspect = *self.rng.pick(&[1.33, 1.333333, 1.5, 1.0, 0.75, 2.0]);
        // The sweep renders at 4:3; the framing takes its height from the pixels.
        let width = self.exact(fov * big_n);
        let big_n = self.exact(big_n);
        let eye = eye.map(|x| self.exact(x));
        let look_w = look.map(|x| self.exact(x * 10.0));
        let up_w = up.map(|x| self.exact(x * 3.0));
        let mut statements: Vec<(&str, Vec<String>)> = vec![
            ("width", vec![self.num(width)]),
            ("image_distance", vec![self.num(big_n)]),
            ("lens_position", eye.map(|x| self.num(x)).to_vec()),
            ("look", look_w.map(|x| self.num(x)).to_vec()),
            ("up", up_w.map(|x| self.num(x)).to_vec()),
        ];
        if self.rng.chance(0.7) {
            statements.push(("aspect_ratio", vec![self.num(aspect)]));
        }
        if self.rng.chance(0.7) {
            let ambient = self.colour(0.0, 0.6);
            statements.push(("ambient_light", ambient.map(|x| self.num(x)).to_vec()));
        }
        // Any order: camera statements may stand anywhere.
        for i in (1..statements.len()).rev() {
            let j = self.rng.int(0, i);
            statements.swap(i, j);
        }
        for (k, v) in statements {
            self.line(k, &v);
        }
        // The basis as the camera computes it, from the values as written.
        let fwd = unit(look_w);
        let right = unit(cross(fwd, up_w));
        let up = cross(right, fwd);
        let half_w = width / 2.0 / big_n;
        View {
            eye,
            fwd,
            right,
            up,
            half_w,
            half_h: half_w * 0.75,
        }
    }

    /// Writes the lens statements last: they may name any object (`focus_on`).
    fn lens(&mut self, bounded: &[usize]) {
        let lens = match self.options.camera {
            Camera::Any => self.rng.chance(0.35),
            Camera::Pinhole => false,
            Camera::Lens => true,
        };
        if !lens {
            if self.rng.chance(0.3) {
                self.single("radius", 0.0);
            }
            let big_n = last_value(&self.out, "image_distance").unwrap_or(8.0);
            // Unused by a pinhole, and still held to f < N (the default 4 too).
            if big_n <= 4.0 || self.rng.chance(0.2) {
                let f = (self.rng.range(0.2, 0.9) * big_n * 1e4).floor() / 1e4;
                self.single("focal_length", f.max(0.0001));
            }
            if self.rng.chance(0.1) {
                self.line("point", &["16".into()]);
            }
            return;
        }
        let n = self.rng.int(1, 64);
        self.line("point", &[n.to_string()]);
        // Focus: by focal length, distance, or on an object.
        match self.rng.int(0, 2) {
            0 => {
                // f < N: N is written; f from the depth in focus.
                let d = self.rng.log_range(2.0, 300.0);
                self.single("focus_distance", d);
            }
            1 if !bounded.is_empty() => {
                let i = *self.rng.pick(bounded);
                self.line("focus_on", &[i.to_string()]);
            }
            _ => {
                // focal_length as a share of N (written earlier): always below it.
                let share = self.rng.range(0.3, 0.98);
                self.out.push_str("# focal_length below image_distance\n");
                let big_n = last_value(&self.out, "image_distance").unwrap_or(8.0);
                let f = (share * big_n * 1e4).floor() / 1e4;
                let f = if f <= 0.0 { big_n / 2.0 } else { f };
                self.single("focal_length", f);
            }
        }
        if self.rng.chance(0.6) {
            let a = self.rng.log_range(0.02, 1.5);
            self.single("radius", a.max(0.001));
        } else {
            let k = *self.rng.pick(&[1.4, 2.0, 2.8, 4.0, 5.6, 8.0, 11.0, 16.0]);
            self.single("f_number", k);
        }
        if self.rng.chance(0.4) {
            let blades = *self.rng.pick(&[0, 3, 5, 6, 7, 8, 9, 12, 16]);
            self.line("aperture_blades", &[blades.to_string()]);
            if self.rng.chance(0.6) {
                let r = self.rng.range(-180.0, 180.0);
                self.single("aperture_rotation", r);
            }
        }
        if self.rng.chance(0.25) {
            let on = if self.rng.chance(0.5) { "on" } else { "off" };
            self.line("adaptive", &[on.into()]);
        }
        if self.rng.chance(0.2) {
            let sampler = if self.rng.chance(0.5) {
                "independent"
            } else {
                "stratified"
            };
            self.line("sampler", &[sampler.into()]);
        }
    }

    fn light(&mut self, view: &View) {
        // Near the scene or far off, up to 300 away from the camera.
        let dist = self.rng.log_range(2.0, 300.0);
        let dir = if self.rng.chance(0.6) {
            unit(add(view.fwd, scaled(self.rng.direction(), 1.2)))
        } else {
            self.rng.direction()
        };
        let at = add(view.eye, scaled(dir, dist));
        self.triple("light_position", at);
        if self.rng.chance(0.8) {
            let i = self.colour(0.0, 1.5);
            self.triple("light_intensity", i);
        }
    }

    fn object(&mut self, shape: &str, view: &View, floor: bool) {
        if self.rng.chance(0.3) {
            let m = *self.rng.pick(&MATERIALS[..]);
            self.line("object", &[shape.into(), m.into()]);
        } else {
            self.line("object", &[shape.into()]);
        }
        // Surface statements, in any order, before or after the transformations.
        let mut surface: Vec<(&str, Vec<String>)> = Vec::new();
        for k in ["Ka", "Kd", "Ks"] {
            if self.rng.chance(0.6) {
                let (lo, hi) = if k == "Ka" { (0.0, 0.4) } else { (0.0, 1.0) };
                let c = self.colour(lo, hi);
                surface.push((k, c.map(|x| self.num(x)).to_vec()));
            }
        }
        if self.rng.chance(0.5) {
            let s = if self.rng.chance(0.2) {
                self.rng.range(0.0, 1.0)
            } else {
                self.rng.log_range(1.0, 128.0)
            };
            surface.push(("shine", vec![self.num(s)]));
        }
        if self.rng.chance(0.5) {
            let s = self.rng.log_range(0.3, 9.0);
            surface.push(("texture", vec![self.num(s)]));
        } else if self.rng.chance(0.1) {
            surface.push(("texture", vec!["0".into()]));
        }
        let ops = if shape == "plane" {
            self.plane_ops(view, floor)
        } else {
            self.solid_ops(view)
        };
        let split = self.rng.int(0, surface.len());
        for (k, v) in &surface[..split] {
            self.line(k, v);
        }
        if self.rng.chance(0.7) {
            self.line("total_transformation", &[ops.len().to_string()]);
        }
        for op in ops {
            match op {
                Op::Scale(s) => self.triple("scale", s),
                Op::Translate(t) => self.triple("translate", t),
                Op::Rotate(axis, deg) => {
                    let a = ["x", "y", "z"][axis];
                    let d = self.num(deg);
                    self.line("rotate", &[a.into(), d]);
                }
            }
        }
        for (k, v) in &surface[split..] {
            self.line(k, v);
        }
    }

    /// A random rotation op.
    fn rotation(&mut self) -> Op {
        let axis = self.rng.int(0, 2);
        let deg = match self.rng.int(0, 3) {
            0 => *self.rng.pick(&[90.0, -90.0, 180.0, 45.0, 30.0, 270.0, 360.0, -45.0]),
            _ => self.rng.range(-360.0, 360.0),
        };
        Op::Rotate(axis, self.exact(deg))
    }

    /// A bounded shape's transformation lines: sized, turned and placed in view.
    fn solid_ops(&mut self, view: &View) -> Vec<Op> {
        // Depth: near, ordinary, or far; size in proportion, tiny to huge.
        let depth = match self.rng.int(0, 9) {
            0 => self.rng.range(1.0, 3.0),
            1 => self.rng.range(200.0, 1000.0),
            _ => self.rng.log_range(3.0, 200.0),
        };
        let size = match self.rng.int(0, 9) {
            0 => self.rng.log_range(0.05, 0.3),
            1 => self.rng.log_range(15.0, 50.0),
            _ => self.rng.log_range(0.3, 15.0),
        };
        // Not much larger than the view at its depth, nor swallowing the lens.
        let size = size.min(depth * (view.half_w + 0.2)).min(depth * 0.4).max(0.02);
        // The shape's own proportions, and mirrors now and then.
        let stretch = [0; 3].map(|_| {
            let s = if self.rng.chance(0.5) {
                1.0
            } else {
                self.rng.log_range(0.4, 1.0)
            };
            if self.rng.chance(0.1) {
                -s
            } else {
                s
            }
        });
        let uniform = self.rng.chance(0.4);
        let scale = if uniform { [size; 3] } else { stretch.map(|s| s * size) };
        // Ops in any order: some before the placing translate, some after.
        let mut before = Vec::new();
        let mut after = Vec::new();
        let split_scale = self.rng.chance(0.2);
        let scale = scale.map(|x| self.exact(x));
        if split_scale {
            before.push(Op::Scale([2.0, 2.0, 2.0]));
            before.push(Op::Scale(scale.map(|x| self.exact(x / 2.0))));
        } else if scale != [1.0; 3] || self.rng.chance(0.5) {
            before.push(Op::Scale(scale));
        }
        for _ in 0..self.rng.int(0, 3) {
            let r = self.rotation();
            let pos = self.rng.int(0, before.len());
            before.insert(pos, r);
        }
        if self.rng.chance(0.2) {
            // A small offset before the scale: the object then turns off-centre.
            let t = [0; 3].map(|_| self.exact_range(-1.0, 1.0));
            before.insert(0, Op::Translate(t));
        }
        if self.rng.chance(0.3) {
            after.push(self.rotation());
        }
        if self.rng.chance(0.1) {
            let s = self.exact_range(0.5, 1.5);
            after.push(Op::Scale([s; 3]));
        }
        // Where its centre goes: inside the view at that depth.
        let (x, y) = (self.rng.range(-0.9, 0.9), self.rng.range(-0.9, 0.9));
        let target = view.at(depth, x, y);
        let centre_before = before.iter().fold([0.0; 3], |p, op| op.apply(p));
        let want = after.iter().rev().fold(target, |p, op| op.unapply(p));
        let t = [0, 1, 2].map(|i| self.exact(want[i] - centre_before[i]));
        let mut ops = before;
        ops.push(Op::Translate(t));
        ops.extend(after);
        // The reach stays well inside Q16.16 (the sweep's scenes are all valid).
        let stretch: f64 = ops.iter().map(|op| op.stretch()).product();
        debug_assert!(stretch * 2.0 < 30000.0);
        ops
    }

    /// A plane's lines: a floor under the camera, or a wall or tilted plane in view.
    fn plane_ops(&mut self, view: &View, floor: bool) -> Vec<Op> {
        let mut ops = Vec::new();
        if self.rng.chance(0.3) {
            let s = [0; 3].map(|_| self.exact_log_range(0.5, 3.0));
            ops.push(Op::Scale(s));
        }
        if self.rng.chance(0.3) {
            ops.push(Op::Rotate(2, self.exact_range(0.0, 360.0)));
        }
        if floor {
            // Normal +z turned to +y: a level floor, or tilted a little.
            ops.push(Op::Rotate(0, -90.0));
            if self.rng.chance(0.4) {
                let axis = *self.rng.pick(&[0, 2]);
                let tilt = self.rng.range(-15.0, 15.0);
                ops.push(Op::Rotate(axis, self.exact(tilt)));
            }
            let below = self.rng.log_range(0.3, 30.0);
            let t = [
                self.exact_range(-50.0, 50.0),
                self.exact(view.eye[1] - below),
                self.exact_range(-50.0, 50.0),
            ];
            ops.push(Op::Translate(t));
        } else {
            for _ in 0..self.rng.int(1, 3) {
                ops.push(self.rotation());
            }
            let depth = self.rng.log_range(5.0, 400.0);
            let at = view.at(depth, self.rng.range(-0.5, 0.5), self.rng.range(-0.5, 0.5));
            ops.push(Op::Translate(at.map(|x| self.exact(x))));
        }
        ops
    }
}

/// The value of the last `keyword v` line in `text`.
fn last_value(text: &str, keyword: &str) -> Option<f64> {
    text.lines()
        .filter_map(|l| {
            let mut w = l.split([' ', '\t']).filter(|w| !w.is_empty());
            (w.next() == Some(keyword)).then(|| w.next()).flatten()
        })
        .filter_map(|w| w.parse::<f64>().ok())
        .next_back()
}

#[cfg(test)]
mod tests {
    use super::*;
    use lensray::{Scene, I16F16};

    #[test]
    fn every_generated_scene_parses_in_both_number_types() {
        for seed in 0..500 {
            for options in [
                Options::default(),
                Options {
                    camera: Camera::Lens,
                    ..Options::default()
                },
            ] {
                let text = generate_with(seed, &options);
                if let Err(e) = Scene::<I16F16>::parse(&text) {
                    panic!("seed {seed} {options:?}: {e}\n{text}");
                }
                let f = Scene::<f32>::parse(&text).unwrap_or_else(|e| panic!("seed {seed}: f32 {e}\n{text}"));
                assert!(!f.objects().is_empty() && !f.lights().is_empty(), "seed {seed}");
                if options.camera == Camera::Lens {
                    assert!(f.camera.radius > 0.0, "seed {seed}: a lens scene without a lens");
                }
            }
        }
    }

    #[test]
    fn seeds_give_their_own_scenes_and_the_same_one_every_time() {
        let a: Vec<String> = (0..50).map(generate).collect();
        let b: Vec<String> = (0..50).map(generate).collect();
        assert_eq!(a, b);
        let distinct: std::collections::BTreeSet<&String> = a.iter().collect();
        assert_eq!(distinct.len(), 50);
        // Pinhole only means pinhole.
        for seed in 0..100 {
            let opts = Options {
                camera: Camera::Pinhole,
                ..Options::default()
            };
            let s = Scene::<f32>::parse(&generate_with(seed, &opts)).unwrap();
            assert_eq!(s.camera.radius, 0.0, "seed {seed}");
        }
    }

    #[test]
    fn the_scenes_cover_the_whole_format() {
        let texts: Vec<String> = (0..500).map(generate).collect();
        let words: std::collections::BTreeSet<String> = texts
            .iter()
            .flat_map(|t| t.lines())
            .filter_map(|l| l.split([' ', '\t']).next())
            .map(str::to_string)
            .collect();
        for k in lensray::KEYWORDS {
            assert!(words.contains(k), "no generated scene uses {k}");
        }
        let has = |s: &str| texts.iter().any(|t| t.contains(s));
        for shape in SHAPES {
            assert!(has(&format!("object {shape}")), "no {shape}");
        }
        for m in MATERIALS {
            assert!(has(&format!(" {m}\n")), "no {m}");
        }
        for s in [
            "rotate x",
            "rotate y",
            "rotate z",
            "shadows on",
            "adaptive on",
            "sampler independent",
            "sampler stratified",
            "\t",
            "ünïcödé",
        ] {
            assert!(has(s), "no {s:?}");
        }
        // Transformations in more than one order: a translate before a rotate and after one.
        let order = |t: &str, first: &str, then: &str| {
            t.split("object").any(|o| {
                let (a, b) = (o.find(first), o.rfind(then));
                matches!((a, b), (Some(a), Some(b)) if a < b)
            })
        };
        assert!(texts.iter().any(|t| order(t, "translate", "rotate")));
        assert!(texts.iter().any(|t| order(t, "rotate", "scale")));
        // Lenses, pinholes, near and far, tiny and huge, many lights.
        let scenes: Vec<Scene<f32>> = texts.iter().map(|t| Scene::parse(t).unwrap()).collect();
        let lenses = scenes.iter().filter(|s| s.camera.radius > 0.0).count();
        assert!((100..300).contains(&lenses), "{lenses} lens scenes of 500");
        assert!(scenes.iter().any(|s| s.lights().len() >= 6));
        assert!(scenes.iter().any(|s| s.objects().len() >= 10));
        assert!(scenes.iter().filter(|s| s.shadows).count() > 150);
        let reach = |s: &Scene<f32>| {
            s.objects()
                .iter()
                .filter_map(|o| o.bound())
                .map(|(c, r)| {
                    let e = s.camera.lens_position;
                    let c = c.to_f64();
                    ((0..3).map(|i| (c[i] - e[i]).powi(2)).sum::<f64>().sqrt(), r as f64)
                })
                .collect::<Vec<_>>()
        };
        let all: Vec<(f64, f64)> = scenes.iter().flat_map(reach).collect();
        assert!(all.iter().any(|&(d, _)| d > 500.0), "far");
        assert!(all.iter().any(|&(d, _)| d < 3.0), "near");
        assert!(all.iter().any(|&(_, r)| r < 0.2), "tiny");
        assert!(all.iter().any(|&(_, r)| r > 40.0), "huge");
    }
}
