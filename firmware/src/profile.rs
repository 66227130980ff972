//! The per-operation profile (feature `profile`): instead of sending rows, the
//! firmware times each operation of the renderer with SysTick and prints one
//! `profile op=NAME calls=N instructions=I` line per operation, so the next
//! optimisation is chosen by measurement.
//!
//! It walks every pixel the way [`lensray::Renderer`] does (the same lens
//! samples, the same rays) and times, through the library's public API:
//! the lens sample, the camera ray, each object's cone test (whether the ray
//! can reach it at all, see `lensray::unstable::cull`), the intersection of each object
//! the cone lets through (by shape, hit or miss, with the nearest hit so far
//! as the limit, as the renderer's nearest-hit search does), the normal at
//! the hit, the whole nearest-hit search and the whole trace.
//! Shading is the trace less the nearest-hit search. The cost of each light
//! comes from further passes with the lights removed one by one from the end:
//! light k costs what the trace with k lights costs more than with k - 1.
//!
//! Each measurement includes a SysTick read-out, whose own cost (measured at
//! the start) is taken off; a tick is 62.5 instructions on the micro:bit, and
//! the mean over many calls is unbiased to a few instructions.

use core::fmt::Write;
use lensray::unstable::lfsr::Lfsr;
use lensray::CameraSample;
use lensray::MAX_LIGHTS;
use lensray::{Renderer, Scalar, Scene, Shape};

use crate::instruction_count::{instructions, Counter};
use crate::semihosting::HostFile;

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
    sample: Stat,
    ray: Stat,
    cone: Stat,
    culled: u64,
    hit: [Stat; SHAPES],
    miss: [Stat; SHAPES],
    normal: Stat,
    closest: Stat,
    trace: Stat,
    trace_hit: Stat,
    pixel: Stat,
}

/// Times `f`, less the read-out's own ticks (`overhead`, scaled by 1024).
#[inline(always)]
fn time<T>(counter: &Counter, overhead: u64, f: impl FnOnce() -> T) -> (T, u64) {
    let t0 = counter.ticks();
    let r = f();
    let t1 = counter.ticks();
    ((r), ((t1 - t0) * 1024).saturating_sub(overhead))
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
        let cam = renderer.camera();
        let rays = renderer.rays_per_pixel();
        for row in 0..rows {
            for col in 0..cols {
                let (_, t) = time(counter, ov, || renderer.pixel(col, row));
                st.pixel.add(t);
                let film = cam.film_point(col, row);
                let mut lfsr = Lfsr::for_pixel(col, row, 0);
                for _ in 0..rays {
                    let (ray, t) = if cam.is_pinhole() {
                        time(counter, ov, || {
                            cam.generate_ray(&CameraSample {
                                film: &film,
                                lens: None,
                            })
                        })
                    } else {
                        let (lens, ts) = time(counter, ov, || cam.lens_sample(&mut lfsr));
                        st.sample.add(ts);
                        time(counter, ov, || {
                            cam.generate_ray(&CameraSample {
                                film: &film,
                                lens: Some(lens),
                            })
                        })
                    };
                    st.ray.add(t);
                    let (o, d, precise) = (ray.origin, ray.dir, ray.precise);
                    let cones = renderer.cones();
                    // Each object as the nearest-hit search meets it: first its cone,
                    // then, if the ray can reach it, the intersection limited by the
                    // nearest hit so far.
                    let mut best: Option<(usize, lensray::unstable::scene::Hit<S>)> = None;
                    for (i, obj) in scene.objects().iter().enumerate() {
                        let (reach, t) = time(counter, ov, || cones.may_reach(i, d));
                        st.cone.add(t);
                        if !reach {
                            st.culled += 1;
                            continue;
                        }
                        let t_max = best.map_or(S::MAX, |(_, h)| h.t);
                        let (h, t) = time(counter, ov, || obj.intersect_dir(o, d, precise, S::HIT_EPSILON, t_max));
                        let k = shape_index(obj.shape);
                        match h {
                            Some(h) => {
                                st.hit[k].add(t);
                                best = Some((i, h));
                            }
                            None => st.miss[k].add(t),
                        }
                    }
                    if let Some((i, h)) = best {
                        let (_, t) = time(counter, ov, || scene.objects()[i].normal(&h, d));
                        st.normal.add(t);
                    }
                    let (_, t) = time(counter, ov, || scene.closest_hit_camera_ray(&ray, cones));
                    st.closest.add(t);
                    let (_, t) = time(counter, ov, || scene.trace_camera_ray(&ray, cones));
                    st.trace.add(t);
                    if best.is_some() {
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
        let cam = renderer.camera();
        let mut sum = 0;
        for row in 0..rows {
            for col in 0..cols {
                let film = cam.film_point(col, row);
                let mut lfsr = Lfsr::for_pixel(col, row, 0);
                for _ in 0..renderer.rays_per_pixel() {
                    let ray = if cam.is_pinhole() {
                        cam.generate_ray(&CameraSample {
                            film: &film,
                            lens: None,
                        })
                    } else {
                        cam.generate_ray(&CameraSample {
                            film: &film,
                            lens: Some(cam.lens_sample(&mut lfsr)),
                        })
                    };
                    let (_, t) = time(counter, ov, || scene.trace_camera_ray(&ray, renderer.cones()));
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
    line("lens-sample", st.sample.calls, st.sample.ticks);
    line("camera-ray", st.ray.calls, st.ray.ticks);
    line("cone-test", st.cone.calls, st.cone.ticks);
    // Calls only (no time of their own): the objects the cone test skipped.
    line("culled-objects", st.culled, 0);
    for (k, (name, _)) in Shape::ALL.iter().enumerate() {
        if st.hit[k].calls + st.miss[k].calls > 0 {
            let mut buf = [0u8; 32];
            line(
                label(&mut buf, "intersect-", name, "-hit"),
                st.hit[k].calls,
                st.hit[k].ticks,
            );
            line(
                label(&mut buf, "intersect-", name, "-miss"),
                st.miss[k].calls,
                st.miss[k].ticks,
            );
        }
    }
    line("nearest-hit-search", st.closest.calls, st.closest.ticks);
    line("normal", st.normal.calls, st.normal.ticks);
    line("trace", st.trace.calls, st.trace.ticks);
    let hits = st.trace_hit.calls;
    line(
        "shading-all-lights",
        hits,
        st.trace.ticks.saturating_sub(st.closest.ticks),
    );
    line(
        "shading-no-light",
        hits,
        with_lights[0].saturating_sub(st.closest.ticks),
    );
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
