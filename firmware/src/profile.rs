//! The per-operation profile (feature `profile`): instead of sending rows, the
//! firmware times each operation of the renderer with SysTick and prints one
//! `profile op=NAME calls=N instructions=I` line per operation, so the next
//! optimisation is chosen by measurement.
//!
//! It times, through the library's public API only: the whole pixel
//! ([`Renderer::pixel`], its own lens points and stop rule), and for each
//! pixel's rays the camera ray ([`Renderer::camera_ray`]), the nearest-hit
//! search ([`Renderer::hit`], split by the shape it finds) and the whole
//! trace ([`Renderer::trace`]). Shading is the trace less the nearest-hit
//! search. The cost of each light comes from further passes with the lights
//! removed one by one from the end ([`Scene::truncate_lights`]): light k
//! costs what the trace with k lights costs more than with k - 1.
//!
//! The per-ray passes cast [`Renderer::rays_per_pixel`] rays a pixel: the
//! chief ray where that is one (a pinhole), else lens points drawn here uniformly on
//! the unit disc (rejection from the square, by a 32-bit LFSR seeded by the
//! pixel). They are not the renderer's own lens points, which its sampler
//! keeps to itself, but rays of the same kind; the `pixel` line is the
//! renderer's own.
//!
//! Each measurement includes a SysTick read-out, whose own cost (measured at
//! the start) is taken off; a tick is 62.5 instructions on the micro:bit, and
//! the mean over many calls is unbiased to a few instructions.

use core::fmt::Write;
use lensray::{Ray, Renderer, Scalar, Scene, Shape, MAX_LIGHTS};

use crate::instruction_count::{instructions, Counter};
use lensray_firmware_cold::semihosting::HostFile;

/// Calls and ticks of one operation.
#[derive(Copy, Clone, Default)]
struct Stat {
    calls: u64,
    ticks: u64,
}

impl Stat {
    fn add(&mut self, ticks: u64) {
        self.calls += 1;
        self.ticks += ticks;
    }
}

/// Shapes in [`Shape::ALL`] order.
const SHAPES: usize = 5;

fn shape_index(s: Shape) -> usize {
    Shape::ALL.iter().position(|(_, x)| *x == s).unwrap_or(0)
}

/// Everything the main pass measures.
#[derive(Default)]
struct Stats {
    pixel: Stat,
    ray: Stat,
    /// The nearest-hit search, by the shape it found.
    hit: [Stat; SHAPES],
    /// The nearest-hit search that found nothing.
    miss: Stat,
    trace: Stat,
    /// The traces whose ray met an object.
    trace_hit: Stat,
}

/// Times `f`, less the read-out's own ticks (`overhead`, scaled by 1024).
#[inline(always)]
fn time<T>(counter: &Counter, overhead: u64, f: impl FnOnce() -> T) -> (T, u64) {
    let t0 = counter.ticks();
    let r = f();
    let t1 = counter.ticks();
    (r, ((t1 - t0) * 1024).saturating_sub(overhead))
}

/// Ticks (× 1024) of an empty measurement.
fn overhead(counter: &Counter) -> u64 {
    let n = 4096u64;
    let mut sum = 0;
    for _ in 0..n {
        let t0 = counter.ticks();
        let t1 = counter.ticks();
        sum += t1 - t0;
    }
    sum * 1024 / n
}

/// A pixel's lens points for the per-ray passes: uniform on the unit disc
/// (Q1.15), from a 32-bit Galois LFSR seeded by the pixel.
struct LensPoints(u32);

impl LensPoints {
    fn for_pixel(col: u32, row: u32) -> Self {
        LensPoints((col.wrapping_mul(0x9E37_79B9) ^ row.wrapping_mul(0x85EB_CA6B)) | 1)
    }

    /// 16 fresh bits: the register clocked 16 times (successive states
    /// are shifted copies of each other).
    fn next_u16(&mut self) -> u16 {
        for _ in 0..16 {
            let lsb = self.0 & 1;
            self.0 >>= 1;
            if lsb == 1 {
                self.0 ^= 0x8020_0003;
            }
        }
        self.0 as u16
    }

    fn next(&mut self) -> (i32, i32) {
        loop {
            let x = self.next_u16() as i16 as i32;
            let y = self.next_u16() as i16 as i32;
            if (x * x) as u32 + (y * y) as u32 <= 1 << 30 {
                return (x, y);
            }
        }
    }
}

/// The rays the per-ray passes cast for pixel (`col`, `row`).
fn rays<'r, S: Scalar>(renderer: &'r Renderer<'_, S>, col: u32, row: u32) -> impl Iterator<Item = Ray<S>> + 'r {
    let pinhole = renderer.rays_per_pixel() == 1;
    let mut lens = LensPoints::for_pixel(col, row);
    (0..renderer.rays_per_pixel()).map(move |_| renderer.camera_ray(col, row, (!pinhole).then(|| lens.next())))
}

/// Runs the profile over `cols` × `rows` pixels with `samples` rays a pixel
/// (`None`: the scene's) and prints the figures on `console`.
pub fn run<S: Scalar>(
    scene: &mut Scene<S>,
    cols: u32,
    rows: u32,
    samples: Option<u32>,
    counter: &Counter,
    console: &mut HostFile,
) {
    let ov = overhead(counter);
    let mut st = Stats::default();
    {
        let renderer = Renderer::new_with_samples(scene, cols, rows, samples);
        let pinhole = renderer.rays_per_pixel() == 1;
        for row in 0..rows {
            for col in 0..cols {
                let (_, t) = time(counter, ov, || renderer.pixel(col, row));
                st.pixel.add(t);
                let mut lens = LensPoints::for_pixel(col, row);
                for _ in 0..renderer.rays_per_pixel() {
                    let p_lens = (!pinhole).then(|| lens.next());
                    let (ray, t) = time(counter, ov, || renderer.camera_ray(col, row, p_lens));
                    st.ray.add(t);
                    let (hit, t) = time(counter, ov, || renderer.hit(&ray));
                    match hit {
                        Some((i, _)) => st.hit[shape_index(renderer.scene().objects()[i].shape)].add(t),
                        None => st.miss.add(t),
                    }
                    let (_, t) = time(counter, ov, || renderer.trace(&ray));
                    st.trace.add(t);
                    if hit.is_some() {
                        st.trace_hit.add(t);
                    }
                }
            }
        }
    }
    // Trace cost with k lights, k = all .. 0 (lights removed from the end).
    let lights = scene.lights().len();
    let mut with_lights = [0u64; MAX_LIGHTS + 1];
    with_lights[lights] = st.trace.ticks;
    for k in (0..lights).rev() {
        scene.truncate_lights(k);
        let renderer = Renderer::new_with_samples(scene, cols, rows, samples);
        let mut sum = 0;
        for row in 0..rows {
            for col in 0..cols {
                for ray in rays(&renderer, col, row) {
                    let (_, t) = time(counter, ov, || renderer.trace(&ray));
                    sum += t;
                }
            }
        }
        with_lights[k] = sum;
    }

    // Ticks × 1024 to instructions.
    let ins = |ticks: u64| instructions(ticks / 1024);
    let mut line = |op: &str, calls: u64, ticks: u64| {
        let _ = writeln!(console, "profile op={op} calls={calls} instructions={}", ins(ticks));
    };
    let pixels = cols as u64 * rows as u64;
    line("pixel", st.pixel.calls, st.pixel.ticks);
    line("camera-ray", st.ray.calls, st.ray.ticks);
    let mut search = st.miss;
    for (k, (name, _)) in Shape::ALL.iter().enumerate() {
        if st.hit[k].calls > 0 {
            let mut buf = [0u8; 32];
            line(
                label(&mut buf, "nearest-hit-", name, ""),
                st.hit[k].calls,
                st.hit[k].ticks,
            );
            search.calls += st.hit[k].calls;
            search.ticks += st.hit[k].ticks;
        }
    }
    line("nearest-hit-none", st.miss.calls, st.miss.ticks);
    line("nearest-hit-search", search.calls, search.ticks);
    line("trace", st.trace.calls, st.trace.ticks);
    let hits = st.trace_hit.calls;
    line("shading-all-lights", hits, st.trace.ticks.saturating_sub(search.ticks));
    line("shading-no-light", hits, with_lights[0].saturating_sub(search.ticks));
    for k in 1..=lights {
        let mut buf = [0u8; 32];
        let mut num = [0u8; 4];
        let n = fmt_u8(&mut num, k as u8);
        line(
            label(&mut buf, "shading-light-", n, ""),
            hits,
            with_lights[k].saturating_sub(with_lights[k - 1]),
        );
    }
    let _ = writeln!(console, "profile-done pixels={pixels} lights={lights}");
}

/// `a + b + c` in `buf`, as a str (labels are ASCII and short).
fn label<'a>(buf: &'a mut [u8; 32], a: &str, b: &str, c: &str) -> &'a str {
    let mut n = 0;
    for s in [a, b, c] {
        for &byte in s.as_bytes() {
            if n < buf.len() {
                buf[n] = byte;
                n += 1;
            }
        }
    }
    core::str::from_utf8(&buf[..n]).unwrap_or("?")
}

/// `k` in decimal.
fn fmt_u8(buf: &mut [u8; 4], k: u8) -> &str {
    let mut n = 0;
    if k >= 100 {
        buf[n] = b'0' + k / 100;
        n += 1;
    }
    if k >= 10 {
        buf[n] = b'0' + (k / 10) % 10;
        n += 1;
    }
    buf[n] = b'0' + k % 10;
    n += 1;
    core::str::from_utf8(&buf[..n]).unwrap_or("?")
}
