//! The scanline filter: a 3-tap filter along the row where a pixel and both
//! its neighbours see only what is far out of focus, a 5-tap where it and
//! four neighbours see only what is twice as far.
//!
//! A point at depth z is spread on the film over a circle of confusion of
//! diameter 2aN |1/z_f − 1/z| (a the lens radius, N the image distance, z_f
//! the depth in focus): K |1 − 1/u| pixels, with u = z/z_f and K = 2aN/(z_f p)
//! for a pixel pitch p. Where everything a pixel's rays meet is spread over
//! at least [`FAR_COC_PIXELS`] pixels (below [`SMALL_PILOT_POINT`] samples,
//! [`SMALL_PILOT_COC_PIXELS`]: see there), the converged picture changes by at
//! most about a quarter of its contrast from one pixel to the next and is
//! nearly linear over three of them, while each pixel's lens integral is
//! still noisy (a frame of near objects, nothing in focus: stratification
//! barely helps there and adaptive sampling stops early). Averaging such a
//! pixel with its neighbours, (1, 2, 1)/4, takes 62 % of the noise's variance
//! away (4.3 dB) at a bias of a quarter of the curvature. A pixel whose rays
//! or whose neighbours' rays meet anything sharper keeps its own value: an
//! edge in focus stays exact. A miss counts as a point at infinity. Lamps
//! (bright objects, [`crate::render::footprint::BRIGHT`]) are apart: the
//! bound above is a share of the contrast, and a lamp's bokeh, clamped to
//! white, has a sharp rim however blurred. So a pixel is filtered only with
//! neighbours whose rays all met lamps as its own did, or all met none; one
//! whose rays met a lamp and something else is on a rim and not filtered,
//! unless every lamp it met is spread over B times the gate, B the
//! brightest lamp's bound in times white
//! ([`crate::render::footprint::BrightFootprints::lamp`]): the picture's
//! change from one pixel to the next is at most its brightest radiance over
//! the blur, so there a rim changes no faster than the edge of an object no
//! brighter than white at the gate, and the pixel counts as meeting none.
//! Where instead everything else it met is in front of every lamp it met
//! and spread over B times the gate, the rim is that occluder's silhouette
//! on the lens (with two things met, the lens points that see the far one
//! are those whose rays pass the near one), which moves across the lens as
//! slowly: the pixel is a soft rim (class 3) and may be mixed with
//! neighbours that all met lamps or with neighbours that met none, not with
//! both at once (seed 12194: a dim sphere 1.6 units from a lens of radius
//! 1.1, in a tenth of every pixel's lens, before a lamp in focus within 4
//! pixels, -2.88 -> +0.10 dB against the floor; seed 11777 at `point` 20, a
//! lamp's highlight through a sliver beside a near cylinder, -2.43 -> +2.92).
//! (Classing a lamp's ray by its own colour instead, a lamp only above
//! white, lost up to 4 dB: a pixel whose few rays missed a lamp's hot part
//! was then mixed across the rim its converged value has.)
//!
//! Where the five pixels around one all see only what is spread over twice
//! that ([`WIDE_COC_FACTOR`]), (1, 4, 6, 4, 1)/16 of them: 73 % of the
//! variance away (5.6 dB). Its second moment is twice the 3-tap's (1 pixel²
//! against ½) and the picture's curvature falls with the square of the
//! blur, so its bias is at most half the 3-tap's at its own gate.
//!
//! Gaps (below `point` 10, where a frame's budget is a ray or two a pixel):
//! anchors every 2 to 4 columns, and the columns between two anchors cast
//! no ray where the anchors say the picture is a line there (see [`fills`]);
//! the rays they leave go to the pixels that cast (`Renderer::gap_period`).
//!
//! Five pixels of state and one anchor ahead, no row buffer: [`Scanline`]
//! yields a row's pixels in order, two pixels ahead (and an anchor). The gate is the same comparison in either number
//! type and the mix is in integers, on the pixels' own values in 256ths of a
//! level ([`Fine`]), rounded once to 8 bits. On with the default
//! stratified, adaptive sampling (from [`FILTER_MIN_POINT`] samples), off
//! with `sampler independent` or `adaptive off`: see
//! [`crate::Renderer::filters`].
//! Measured in `host-tests/examples/coc_filter_probe.rs` (BENCHMARKS.md).

use crate::camera::CameraParams;
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::render::defocus::Defocus;
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};

/// The smallest circle of confusion, in pixels, that lets a pixel be
/// filtered from [`SMALL_PILOT_POINT`] samples (4: no lens scene of scenes/
/// lost at 320×240 and generated frames gained about the most; 2 lost 1.9 dB
/// on `paper-fig8-pinhole`, 3 lost 0.09 dB a seed at `point` 20 to 40).
pub const FAR_COC_PIXELS: f64 = 4.0;

/// The gate below [`SMALL_PILOT_POINT`] samples, where a pixel takes 4 rays
/// or fewer before any check (a quarter of a pilot of 16, four times its
/// noise): the filter's bias falls with the square of the blur, so half the
/// blur is worth there what 4 pixels are above. Generated scenes at 320×240
/// and `point` 3 to 19 met both floors 320 times in 340 with it, 312 with 4.
pub const SMALL_PILOT_COC_PIXELS: f64 = 2.0;

/// The fewest samples whose gate is [`FAR_COC_PIXELS`]: where the pilot is
/// 8 (`ADAPTIVE_EIGHT_POINT`, asserted where both are seen).
pub const SMALL_PILOT_POINT: u32 = 20;

/// The filter's gate, in pixels, for a frame of `samples` lens samples a pixel.
pub fn far_coc_pixels(samples: u32) -> f64 {
    if samples < SMALL_PILOT_POINT {
        SMALL_PILOT_COC_PIXELS
    } else {
        FAR_COC_PIXELS
    }
}

/// How many times [`FAR_COC_PIXELS`] a pixel's and its four neighbours'
/// circles of confusion must all span for the 5-tap (1, 4, 6, 4, 1)/16.
pub const WIDE_COC_FACTOR: i32 = 2;

/// The class bit of a pixel whose rays all met something spread over
/// [`WIDE_COC_FACTOR`] times [`FAR_COC_PIXELS`] or more.
pub const WIDE: u8 = 4;

/// The fewest samples a pixel must have for rows to be filtered: wherever
/// there is a ray budget, every `point` (`ADAPTIVE_BUDGET_POINT`, asserted
/// where both are seen). From 10 rather than 20 it gained on 28 of 29 changed
/// seeds of 1000, 3000, 6000-6059 at 80x60; from 5 rather than 10 on all 13
/// changed there and in 8200-8239 (6007 +4.3 dB, 1050 -3.82 -> +0.20 dB
/// against `point` independent samples); at 1 to 4 it is what lets a ray or
/// two a pixel meet the floors at all, with gaps.
pub const FILTER_MIN_POINT: u32 = 1;

/// K / T: the circle of confusion of a point at infinity in pixels of an
/// image `cols` wide, over [`FAR_COC_PIXELS`] (twice that below
/// [`SMALL_PILOT_POINT`] samples: [`Defocus::gated`]); 0 for a pinhole or a camera
/// focused nowhere. Set-up only, in f64.
pub fn far_ratio(cam: &CameraParams, cols: u32) -> f64 {
    let z_f = cam.focus_depth();
    let p = cam.width / cols.max(1) as f64;
    let k = 2.0 * cam.radius * cam.image_distance / (z_f * p);
    if k.is_finite() && k > 0.0 {
        // Q16.16's range: a ratio beyond it filters as much as any.
        k.min(16384.0) / FAR_COC_PIXELS
    } else {
        0.0
    }
}

impl<S: Scalar> Defocus<S> {
    /// This defocus with the scanline filter's gate for `cam` at `cols` pixels across.
    pub fn with_far(mut self, cam: &CameraParams, cols: u32) -> Self {
        self.far = if self.radius() == S::ZERO {
            S::ZERO
        } else {
            S::from_f64(far_ratio(cam, cols))
        };
        self
    }

    /// This defocus with the gate of a frame of `samples` a pixel
    /// ([`far_coc_pixels`]): K/T doubled below [`SMALL_PILOT_POINT`]. Per
    /// frame, not baked: a renderer's samples may change after set-up.
    #[inline]
    pub fn gated(mut self, samples: u32) -> Self {
        const _: () = assert!(FAR_COC_PIXELS == 2.0 * SMALL_PILOT_COC_PIXELS);
        if samples < SMALL_PILOT_POINT {
            self.far = self.far.add(self.far);
        }
        self
    }

    /// Whether a point at distance `t` along unit `d` is spread over at least
    /// the gate T ([`far_coc_pixels`]; K |1 − 1/u| >= T, as (K/T) |u − 1| > u for u > 0),
    /// over [`WIDE_COC_FACTOR`] times that (the 5-tap's gate), and over
    /// `lamp` times that (a lamp's hit that may be mixed across its bokeh's
    /// rim, `lamp` its bound in times white; 0 never): one depth ratio and
    /// one spread for the three. Also the depth ratio u itself (which of two
    /// hits is in front).
    #[inline]
    pub fn far_hits(&self, d: Vec3<S>, t: S, lamp: u16) -> (bool, bool, bool, S) {
        let u = self.depth_ratio(d, t);
        let spread = self.far.mul(u.sub(S::ONE).abs());
        let pos = u > S::ZERO;
        (
            pos && spread > u,
            pos && spread > u.mul(S::from_i32(WIDE_COC_FACTOR)),
            pos && lamp != 0 && spread > u.mul(S::from_i32(lamp as i32)),
            u,
        )
    }

    /// Whether a miss is spread over [`WIDE_COC_FACTOR`] times the gate.
    #[inline]
    pub fn wide_miss(&self) -> bool {
        self.far > S::from_i32(WIDE_COC_FACTOR)
    }

    /// Whether a miss (a point at infinity, spread over K pixels) is far out of focus.
    #[inline]
    pub fn far_miss(&self) -> bool {
        self.far > S::ONE
    }
}

/// `(a + 2b + c) / 4`, per channel, rounded once from [`Fine`] steps (from
/// 8-bit levels, `(a + 2b + c + 2) / 4`).
#[inline]
fn mix(a: Fine, b: Fine, c: Fine) -> Rgb888 {
    let m = |i: usize| ((a.0[i] as u32 + 2 * b.0[i] as u32 + c.0[i] as u32 + 512) >> 10) as u8;
    Rgb888::new(m(0), m(1), m(2))
}

/// `(a + 4b + 6c + 4d + e) / 16`, per channel, rounded once from [`Fine`]
/// steps (from 8-bit levels, `(a + 4b + 6c + 4d + e + 8) / 16`).
#[inline]
fn mix5(a: Fine, b: Fine, c: Fine, d: Fine, e: Fine) -> Rgb888 {
    let m = |i: usize| {
        let v = [a, b, c, d, e].map(|p| p.0[i] as u32);
        ((v[0] + 4 * v[1] + 6 * v[2] + 4 * v[3] + v[4] + 2048) >> 12) as u8
    };
    Rgb888::new(m(0), m(1), m(2))
}

/// The class bit of a pixel some ray of which met a checkered surface (with
/// gaps only, see [`fills`]; the filter ignores it).
pub const TEXTURED: u8 = 8;

/// The class bits the filter compares: the lamp classes and [`WIDE`].
const FILTER_BITS: u8 = 3 | WIDE;

/// A pixel's colour in 256ths of an 8-bit level a channel, truncated
/// ([`crate::number::Scalar`]'s `to_fine`): the row carries it so that a gap
/// takes the line between its anchors' own means, rounded once (rounded
/// anchors a level apart left a gap between them a level off in one case in
/// four on smooth shading: seed 9009 at `point` 5, 7,593 channels a level off
/// against 492 of `point` independent samples).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Fine(pub [u16; 3]);

impl Fine {
    /// Black.
    pub const BLACK: Fine = Fine([0; 3]);

    /// A mean colour's channels, each clamped to [0, 1].
    #[inline]
    pub fn of<S: Scalar>(c: Vec3<S>) -> Self {
        Fine([c.x.to_fine(), c.y.to_fine(), c.z.to_fine()])
    }

    /// The 8-bit colour, rounded: exactly `to_u8` of the channels it came from.
    #[inline]
    pub fn rgb(self) -> Rgb888 {
        let [r, g, b] = self.0.map(|c| ((c as u32 + 128) >> 8) as u8);
        Rgb888::new(r, g, b)
    }
}

impl From<Rgb888> for Fine {
    /// An 8-bit colour's levels, no fraction.
    fn from(c: Rgb888) -> Self {
        Fine([c.r(), c.g(), c.b()].map(|v| (v as u16) << 8))
    }
}

/// [`GAP_LEVELS`] of the loose rule, on any surface: the rungs a frame's
/// gap survey climbs until a pixel that casts has a ray (255: every gap
/// fills, 25 % of the pixels cast at period 4, within 40 % of `point` 1).
pub const GAP_LOOSE_LEVELS: [u8; 4] = [8, 24, 64, 255];

/// The most a gap's two anchors may differ, in levels on every channel, for
/// the gap to take their mean whatever their classes (see [`fills`]): on
/// their own values ([`Fine`]), less than `GAP_LEVELS + 1` apart, the
/// widest two pixels a level apart could be (on their rounded levels, 9.4
/// and 10.6 read 2 apart and cast; seeds 9000-9219 by twenties at 160x120,
/// `point` 1 to 9: 525 -> 527 of 540 frames meet both floors, none lost).
pub const GAP_LEVELS: u8 = 1;

/// Whether the gap pixels between two anchors `left` and `right` (colour and
/// class) cast no ray and take the line between them: where both see only
/// what is spread over twice the filter's gate (the 5-tap's class: the
/// picture is nearly linear over a few pixels there) and share a lamp class,
/// or where their own values ([`Fine`]) are less than [`GAP_LEVELS`] + 1
/// apart on every channel and neither met a checker (unless both are out
/// of focus). `loose` above 0: less than that many levels + 1 apart (a
/// rung of [`GAP_LOOSE_LEVELS`]), on any surface where `checkers`, else as
/// the strict rule off checkers, for frames where the strict rule fills too
/// few gaps to leave a ray a pixel (see `Renderer::gap_period`).
#[inline]
pub fn fills(left: (Fine, u8), right: (Fine, u8), loose: u8, checkers: bool) -> bool {
    let (a, b) = (left.0, right.0);
    // Less than one level more than the rule's levels, in 256ths.
    let most = ((if loose > 0 { loose } else { GAP_LEVELS } as u32) << 8) + 255;
    let close = |i: usize| (a.0[i] as u32).abs_diff(b.0[i] as u32) <= most;
    // A checker may hide a square between two anchors of one colour.
    let smooth = (loose > 0 && checkers) || (left.1 | right.1) & TEXTURED == 0 || left.1 & right.1 & 3 != 0;
    let near = smooth && close(0) && close(1) && close(2);
    let both = left.1 & right.1;
    let far = both & 3 != 0 && both & WIDE != 0;
    far || near
}

/// The gap `d` of `period` columns right of anchor `left`, on the line to
/// anchor `right` (in [`Fine`] steps, rounded), with their class where they
/// share it, else 0.
#[inline]
pub(crate) fn interpolate(left: (Fine, u8), right: (Fine, u8), d: u32, period: u32) -> (Fine, u8) {
    let (a, b) = (left.0 .0, right.0 .0);
    let m = |i: usize| ((a[i] as u32 * (period - d) + b[i] as u32 * d + period / 2) / period) as u16;
    // A soft rim's anchor (3) beside one of a single lamp class: that class.
    let (both, either) = (left.1 & right.1, left.1 | right.1);
    let class = if left.1 == right.1 {
        left.1
    } else if either & 3 == 3 && both & 3 != 0 {
        both & FILTER_BITS
    } else {
        0
    };
    (Fine([m(0), m(1), m(2)]), class)
}

/// A row's pixels, filtered, in order from column 0 (see the module): from
/// `pixel`, which renders column c as its colour, its rays and its class: 0
/// where some ray met something within [`FAR_COC_PIXELS`] (see
/// [`Defocus::far_hits`]) or met both a lamp and something else (unless
/// every lamp's hit passed its gate: then 2; or every other hit passed it in
/// front of every lamp's: then 3, a soft rim), else 1 if they all met lamps,
/// 2 if none did, with [`WIDE`] where every ray passed the 5-tap's gate. A
/// pixel is filtered where it and both neighbours hold one class, 1 or 2 (3
/// holds both; the 5-tap where it and two each side do, all with [`WIDE`]); the
/// filter ignores [`TEXTURED`], which only gaps read. With gaps
/// ([`Scanline::with_gaps`]) a gap's columns are rendered after the anchor
/// on their right, or not at all.
pub struct Scanline<F> {
    pixel: F,
    /// The next column to yield.
    col: u32,
    cols: u32,
    /// Columns `col − 2` to `col + 2` as rendered, and their classes
    /// (0 beyond the row's ends: no filter there).
    window: [(Fine, u8); 5],
    /// Lens rays cast so far.
    rays: u32,
    /// Whether the row is filtered at all; without it each pixel is passed on as it comes.
    filter: bool,
    /// Gaps (see [`fills`]): anchors every `period` columns from `phase`, or `None`.
    gaps: Option<(u32, u32, u8, bool)>,
    /// The last anchor fetched.
    left: (Fine, u8),
    /// The anchor right of the gaps being fetched, rendered before them.
    right: Option<(Fine, u8)>,
    /// Whether those gaps are filled.
    fill: bool,
}

impl<F: FnMut(u32) -> (Fine, u32, u8)> Scanline<F> {
    /// The first `cols` pixels of a row of `pixel`.
    pub fn new(pixel: F, cols: u32) -> Self {
        Scanline {
            pixel,
            col: 0,
            cols,
            window: [(Fine::BLACK, 0); 5],
            rays: 0,
            filter: true,
            gaps: None,
            left: (Fine::BLACK, 0),
            right: None,
            fill: false,
        }
    }

    /// The same row, filtered only if `filter` (else each pixel as it comes).
    pub fn with_filter(mut self, filter: bool) -> Self {
        self.filter = filter;
        self
    }

    /// The same row with gaps: anchors at columns `phase`, `phase + period`
    /// ... (`period` 2 to 4); the columns between two anchors cast no ray and
    /// take the line between them where [`fills`] allows, else are rendered,
    /// after the anchor on their right. Filtered rows only.
    pub fn with_gaps(mut self, gaps: Option<(u32, u32, u8, bool)>) -> Self {
        self.gaps = gaps
            .filter(|&(period, ..)| period >= 2)
            .map(|(period, phase, loose, checkers)| (period, phase % period, loose, checkers));
        self
    }

    /// Column `k` as rendered or filled (`k` = 0, 1, 2 ... in turn).
    fn fetch(&mut self, k: u32) -> (Fine, u8) {
        let Some((period, phase, loose, checkers)) = self.gaps else {
            return self.render(k);
        };
        let offset = (k + period - phase) % period;
        if offset == 0 {
            let p = match self.right.take() {
                Some(p) => p,
                None => self.render(k),
            };
            self.left = p;
            return p;
        }
        if self.right.is_none() {
            // The first gap of a run: its anchors, if it has both.
            let next = k + (period - offset);
            self.fill = false;
            // Before the row's first anchor there is none on the left.
            if k >= offset && next < self.cols {
                let p = self.render(next);
                self.right = Some(p);
                self.fill = fills(self.left, p, loose, checkers);
            }
        }
        match self.right {
            Some(right) if self.fill => interpolate(self.left, right, offset, period),
            _ => self.render(k),
        }
    }

    /// The lens rays the pixels yielded so far (and the two ahead) cast.
    pub fn rays(&self) -> u32 {
        self.rays
    }

    fn render(&mut self, col: u32) -> (Fine, u8) {
        let (c, n, class) = (self.pixel)(col);
        self.rays = self.rays.saturating_add(n);
        (c, class)
    }
}

impl<F: FnMut(u32) -> (Fine, u32, u8)> Iterator for Scanline<F> {
    type Item = Rgb888;

    fn next(&mut self) -> Option<Rgb888> {
        let col = self.col;
        if col >= self.cols {
            return None;
        }
        if cfg!(feature = "no-scanline-filter") || !self.filter {
            // No window where nothing is filtered: the micro:bit's flash and cycles.
            self.col = col + 1;
            return Some(self.render(col).0.rgb());
        }
        if col == 0 {
            self.window[2] = self.fetch(0);
            if self.cols > 1 {
                self.window[3] = self.fetch(1);
            }
        }
        self.window[4] = if col + 2 < self.cols {
            self.fetch(col + 2)
        } else {
            (Fine::BLACK, 0)
        };
        let [a2, a, b, c, c2] = self.window;
        self.window = [a, b, c, c2, (Fine::BLACK, 0)];
        self.col = col + 1;
        // The lamp classes the three and the five share (a soft rim's, 3, shares both).
        let three = a.1 & b.1 & c.1;
        let five = three & a2.1 & c2.1;
        Some(if five & WIDE != 0 && five & 3 != 0 {
            mix5(a2.0, a.0, b.0, c.0, c2.0)
        } else if three & 3 != 0 {
            mix(a.0, b.0, c.0)
        } else {
            b.0.rgb()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row of given pixels through a [`Scanline`] (with `gaps`): what it
    /// yields, the columns it asked for in order, and the rays it counted.
    fn run(row: &[(Fine, u32, u8)], gaps: Option<(u32, u32, u8, bool)>) -> (Vec<Rgb888>, Vec<u32>, u32) {
        let mut asked = Vec::new();
        let mut line = Scanline::new(
            |col| {
                asked.push(col);
                row[col as usize]
            },
            row.len() as u32,
        )
        .with_gaps(gaps);
        let out: Vec<Rgb888> = (&mut line).collect();
        let rays = line.rays();
        (out, asked, rays)
    }

    /// A random colour in [`Fine`] steps (any fraction of a level).
    fn random_fine(next: &mut impl FnMut() -> u32) -> Fine {
        Fine([0; 3].map(|_| (next() % 65281) as u16))
    }

    /// Random rows of random classes: a pixel is the 5-tap mix exactly where
    /// it and its four neighbours all have [`WIDE`] and hold one lamp class
    /// (1 or 2; a soft rim, 3, holds both), else the 3-tap mix where it and
    /// both neighbours hold one (never at a row's ends), else itself; every
    /// pixel is rendered once, in order, and its rays counted.
    #[test]
    fn a_pixel_is_mixed_only_between_neighbours_of_its_own_class() {
        let mut next = crate::test_rng::xorshift32(0x5ca1_ab1e);
        let (mut mixed, mut wide_mixed, mut kept) = (0, 0, 0);
        for len in 1..60u32 {
            // Classes in runs (four in five pixels keep the last one's).
            let mut class = 0u8;
            let row: std::vec::Vec<(Fine, u32, u8)> = (0..len)
                .map(|_| {
                    let c = random_fine(&mut next);
                    if next().is_multiple_of(5) {
                        class = [0, 1, 2, 2, 2, 6, 6, 6, 5, 3, 7, 7][(next() % 12) as usize];
                    }
                    (c, next() % 70, class)
                })
                .collect();
            let (out, asked, rays) = run(&row, None);
            assert_eq!(rays, row.iter().map(|p| p.1).sum::<u32>());
            assert_eq!(asked, (0..len).collect::<std::vec::Vec<_>>());
            for c in 0..len as usize {
                let inner = c > 0 && c + 1 < len as usize;
                let wide = c > 1 && c + 2 < len as usize;
                // Pixels `range` all hold lamp class 1 or all hold 2.
                let hold = |range: std::ops::RangeInclusive<usize>, bits: u8| {
                    [1u8, 2].iter().any(|&k| {
                        range
                            .clone()
                            .all(|i| row[i].2 & bits == bits && matches!(row[i].2 & 3, x if x == k || x == 3))
                    })
                };
                if wide && hold(c - 2..=c + 2, WIDE) {
                    let p = |i: usize| row[i].0;
                    assert_eq!(
                        out[c],
                        mix5(p(c - 2), p(c - 1), p(c), p(c + 1), p(c + 2)),
                        "len {len} col {c}"
                    );
                    wide_mixed += 1;
                } else if inner && hold(c - 1..=c + 1, 0) {
                    assert_eq!(out[c], mix(row[c - 1].0, row[c].0, row[c + 1].0), "len {len} col {c}");
                    mixed += 1;
                } else {
                    assert_eq!(out[c], row[c].0.rgb(), "len {len} col {c}");
                    kept += 1;
                }
            }
        }
        assert!(
            mixed > 50 && wide_mixed > 20 && kept > 50,
            "{mixed} mixed, {wide_mixed} wide, {kept} kept"
        );
    }

    /// Random rows with gaps of every period and phase: a gap's columns cast
    /// no ray exactly where both its anchors are in the row and [`fills`]
    /// holds for them, and then take the rounded line between them; every
    /// other column is rendered once, a gap's after the anchor on its right;
    /// the rays are those of the columns rendered, and the row is filtered as
    /// a row of those pixels without gaps would be.
    #[test]
    fn a_gap_casts_no_ray_exactly_where_its_anchors_fill_it() {
        let mut next = crate::test_rng::xorshift32(0x6a95_0001);
        let (mut filled, mut rendered_gaps) = (0, 0);
        for len in 1..80u32 {
            let period = 2 + next() % 3;
            let phase = next() % period;
            let loose = [0, 0, GAP_LOOSE_LEVELS[0], GAP_LOOSE_LEVELS[1], 255][(next() % 5) as usize];
            let checkers = next().is_multiple_of(2);
            // Runs of near colours and classes, so that both answers occur.
            let mut base = [0u8; 3];
            let mut class = 0u8;
            let row: std::vec::Vec<(Fine, u32, u8)> = (0..len)
                .map(|_| {
                    if next().is_multiple_of(4) {
                        base = [next() as u8, next() as u8, next() as u8];
                        class = [0, 2, 6, 5, 8, 14, 1, 3, 7][(next() % 9) as usize];
                    }
                    // Within about two levels of the run's base, any fraction.
                    let mut jitter = |b: u8| ((b as u32 * 256 + next() % 640).min(65280)) as u16;
                    let c = Fine([jitter(base[0]), jitter(base[1]), jitter(base[2])]);
                    (c, 1 + next() % 5, class)
                })
                .collect();
            // The model: which columns are filled, and the pixels before the filter.
            let mut expected: std::vec::Vec<(Fine, u32, u8)> = row.clone();
            let mut cast = vec![true; len as usize];
            for k in 0..len {
                let offset = (k + period - phase) % period;
                let (l, r) = (k.checked_sub(offset), k + period - offset);
                if offset == 0 || l.is_none() || r >= len {
                    continue;
                }
                let (l, r) = (row[l.unwrap() as usize], row[r as usize]);
                if fills((l.0, l.2), (r.0, r.2), loose, checkers) {
                    let (c, class) = interpolate((l.0, l.2), (r.0, r.2), offset, period);
                    for i in 0..3 {
                        // The line between the anchors' own values, in levels, rounded
                        // once (off by one only within 1/256 of a level of a half).
                        let (x, y) = (l.0 .0[i] as f64 / 256.0, r.0 .0[i] as f64 / 256.0);
                        let line = (x * (period - offset) as f64 + y * offset as f64) / period as f64;
                        let got = [c.rgb().r(), c.rgb().g(), c.rgb().b()][i] as f64;
                        let near_half = ((line + 0.5).fract() - 0.5).abs() > 0.5 - 1.0 / 256.0;
                        assert!(got == (line + 0.5).floor() || near_half, "{line} -> {got}");
                    }
                    expected[k as usize] = (c, 0, class);
                    cast[k as usize] = false;
                    filled += 1;
                } else {
                    rendered_gaps += 1;
                }
            }
            let (out, asked, line_rays) = run(&row, Some((period, phase, loose, checkers)));
            let rays: u32 = row.iter().zip(&cast).filter(|(_, &c)| c).map(|(p, _)| p.1).sum();
            assert_eq!(line_rays, rays, "len {len} period {period} phase {phase}");
            let mut sorted = asked.clone();
            sorted.sort();
            let want: std::vec::Vec<u32> = (0..len).filter(|&k| cast[k as usize]).collect();
            assert_eq!(sorted, want, "each column cast is rendered once");
            for (i, &k) in asked.iter().enumerate() {
                // A column rendered out of order is an anchor with a gap just left of it.
                if let Some(&later) = asked[i + 1..].iter().find(|&&j| j < k) {
                    assert!(
                        !(later + period - phase).is_multiple_of(period) && k - later < period,
                        "{asked:?}"
                    );
                }
            }
            let plain: std::vec::Vec<Rgb888> = Scanline::new(|col| expected[col as usize], len).collect();
            assert_eq!(out, plain, "len {len} period {period} phase {phase}");
        }
        assert!(
            filled > 100 && rendered_gaps > 100,
            "{filled} filled, {rendered_gaps} rendered"
        );
    }

    /// (a + 4b + 6c + 4d + e) / 16 per channel from [`Fine`] values, against
    /// its definition in f64 in levels, rounded half up.
    #[test]
    fn mix5_is_the_rounded_binomial_mean() {
        let mut next = crate::test_rng::xorshift32(11);
        for _ in 0..10_000 {
            let p: [Fine; 5] = core::array::from_fn(|_| random_fine(&mut next));
            let want = |i: usize| {
                let v = [1.0, 4.0, 6.0, 4.0, 1.0]
                    .iter()
                    .zip(&p)
                    .map(|(w, c)| w * c.0[i] as f64 / 256.0)
                    .sum::<f64>();
                (v / 16.0 + 0.5).floor() as u8
            };
            let expected = Rgb888::new(want(0), want(1), want(2));
            assert_eq!(mix5(p[0], p[1], p[2], p[3], p[4]), expected);
        }
    }

    /// (a + 2b + c) / 4 per channel from [`Fine`] values, against its
    /// definition in f64 in levels, rounded half up; from whole levels, as
    /// `(a + 2b + c + 2) / 4` of the 8-bit colours.
    #[test]
    fn mix_is_the_rounded_weighted_mean() {
        let mut next = crate::test_rng::xorshift32(7);
        for _ in 0..10_000 {
            let (a, b, c) = (random_fine(&mut next), random_fine(&mut next), random_fine(&mut next));
            let want = |i: usize| ((a.0[i] as f64 + 2.0 * b.0[i] as f64 + c.0[i] as f64) / 1024.0 + 0.5).floor() as u8;
            assert_eq!(mix(a, b, c), Rgb888::new(want(0), want(1), want(2)));
            let (a, b, c) = (a.rgb(), b.rgb(), c.rgb());
            let m = |x: u8, y: u8, z: u8| ((x as u16 + 2 * y as u16 + z as u16 + 2) >> 2) as u8;
            assert_eq!(
                mix(a.into(), b.into(), c.into()),
                Rgb888::new(m(a.r(), b.r(), c.r()), m(a.g(), b.g(), c.g()), m(a.b(), b.b(), c.b()))
            );
        }
    }

    /// The strict rule fills between anchors without a checker exactly where
    /// their own values are less than two levels apart on every channel
    /// (9.4 and 10.6 fill, though their rounded levels 9 and 11 are two
    /// apart); with a checker on either (not both far out of focus) only a
    /// loose rung on checkers fills, less than its levels + 1 apart; off
    /// checkers, none does.
    #[test]
    fn anchors_fill_on_their_own_values() {
        let f = |v: f64| Fine([(v * 256.0) as u16; 3]);
        assert!(fills((f(9.4), 0), (f(10.6), 0), 0, true));
        assert!(!fills((f(9.4), 0), (f(11.45), 0), 0, true));
        let mut next = crate::test_rng::xorshift32(0xf111);
        let (mut yes, mut no) = (0, 0);
        for _ in 0..20_000 {
            let a = random_fine(&mut next);
            // Near a, within about three levels each way.
            let b = Fine(a.0.map(|v| (v as i32 + (next() % 1536) as i32 - 768).clamp(0, 65280) as u16));
            let apart = |most: u32| (0..3).all(|i| (a.0[i] as u32).abs_diff(b.0[i] as u32) < most);
            let want = apart(2 * 256);
            for checkers in [false, true] {
                assert_eq!(fills((a, 0), (b, 0), 0, checkers), want, "{a:?} {b:?}");
                assert!(!fills((a, TEXTURED), (b, 0), 0, checkers), "{a:?} {b:?}");
                // Off checkers a loose rung is the strict rule there.
                assert!(!fills((a, TEXTURED), (b, 2), 8, false), "{a:?} {b:?}");
                // Off checkers, elsewhere, it is still loose.
                assert_eq!(fills((a, 2), (b, 2), 8, checkers), apart(9 * 256), "{a:?} {b:?}");
            }
            assert_eq!(fills((a, TEXTURED), (b, 2), 8, true), apart(9 * 256), "{a:?} {b:?}");
            if want {
                yes += 1;
            } else {
                no += 1;
            }
        }
        assert!(yes > 1000 && no > 1000, "{yes} fill, {no} cast");
    }

    /// A gap between anchors a level apart takes the line between their own
    /// values: 9.3 and 9.6 levels give 9 (9.45), where their rounded levels
    /// 9 and 10 gave 10; 9.3 and 9.8 give 10 (9.55).
    #[test]
    fn a_gap_rounds_its_anchors_line_once() {
        let f = |v: f64| Fine([(v * 256.0) as u16; 3]);
        let gap = |a: f64, b: f64| interpolate((f(a), 0), (f(b), 0), 1, 2).0.rgb().r();
        assert_eq!(gap(9.3, 9.6), 9);
        assert_eq!(gap(9.3, 9.8), 10);
        assert_eq!(gap(9.0, 10.0), 10);
    }
}
