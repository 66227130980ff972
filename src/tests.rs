//! Renders of small scenes into embedded-graphics' `MockDisplay`, and the
//! shading rules checked against an f64 evaluation of SPEC section 4.

use crate::{render, render_with, Renderer, Scalar, Scene, I16F16};
use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::{BinaryColor, Rgb565, Rgb888};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;

/// A white unit sphere at depth 8 on black, pinhole, film 4 wide.
const HEAD_ON: &str = "width 4\nambient_light 1 1 1\nobject sphere\nKa 1 1 1\nKd 0 0 0\ntranslate 0 0 -8\n";

fn render_binary<S: Scalar>(text: &str, w: u32, h: u32) -> MockDisplay<BinaryColor> {
    let scene = Scene::<S>::parse(text).unwrap();
    let mut display = MockDisplay::<BinaryColor>::new();
    let mut panel = display.cropped(&Rectangle::new(Point::zero(), Size::new(w, h)));
    render(&scene, &mut panel).unwrap();
    display
}

#[test]
fn sphere_head_on_is_a_disc() {
    // Chief rays hit the sphere where u² + v² < 64/63 on the film: the four
    // centre pixels and their four neighbours, nothing at the diagonals.
    let pattern = [
        "........", //
        "........", //
        "...##...", //
        "..####..", //
        "..####..", //
        "...##...", //
        "........", //
        "........", //
    ];
    render_binary::<I16F16>(HEAD_ON, 8, 8).assert_pattern(&pattern);
    render_binary::<f32>(HEAD_ON, 8, 8).assert_pattern(&pattern);
}

#[test]
fn picture_is_upright_and_not_mirrored() {
    // A sphere of radius 1/2 at (1, 1, -8) projects onto the film around (1, 1):
    // the 2x2 pixels of centres (0.75 | 1.25, 0.75 | 1.25), top right.
    let text = "width 4\nambient_light 1 1 1\nobject sphere\nKa 1 1 1\nscale 0.5 0.5 0.5\ntranslate 1 1 -8\n";
    render_binary::<I16F16>(text, 8, 8).assert_pattern(&[
        "........", //
        ".....##.", //
        ".....##.", //
        "........", //
        "........", //
        "........", //
        "........", //
        "........", //
    ]);
}

#[test]
fn renders_rgb565_through_embedded_graphics_conversion() {
    let scene = Scene::<I16F16>::parse("ambient_light 1 1 1\nobject sphere\nKa 1 0 0\ntranslate 0 0 -8\n").unwrap();
    let mut display = MockDisplay::<Rgb565>::new();
    render(&scene, &mut display).unwrap();
    assert_eq!(display.get_pixel(Point::new(32, 32)), Some(Rgb565::RED));
    assert_eq!(display.get_pixel(Point::new(0, 0)), Some(Rgb565::BLACK));
}

#[test]
fn empty_and_tiny_targets_never_panic() {
    let scene = Scene::<I16F16>::parse(include_str!("../scenes/paper-program1.scene")).unwrap();
    for (w, h) in [(0, 0), (0, 5), (5, 0), (1, 1), (3, 1), (1, 3)] {
        let mut display = MockDisplay::<Rgb888>::new();
        let mut panel = display.cropped(&Rectangle::new(Point::new(10, 10), Size::new(w, h)));
        render(&scene, &mut panel).unwrap();
        let drawn = display.affected_area();
        assert_eq!(
            drawn.size,
            Size::new(w, h).component_min(Size::new(w * h.min(1), h * w.min(1)))
        );
    }
}

#[test]
fn one_fill_per_row_and_rows_match_pixels() {
    // A target that counts fill_contiguous calls and records what they drew.
    struct Rows {
        fills: u32,
        px: [[Rgb888; 6]; 4],
    }
    impl OriginDimensions for Rows {
        fn size(&self) -> Size {
            Size::new(6, 4)
        }
    }
    impl DrawTarget for Rows {
        type Color = Rgb888;
        type Error = core::convert::Infallible;
        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, _: I) -> Result<(), Self::Error> {
            panic!("the renderer should draw whole rows");
        }
        fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
            &mut self,
            area: &Rectangle,
            colors: I,
        ) -> Result<(), Self::Error> {
            assert_eq!(area.size.height, 1);
            self.fills += 1;
            for (x, c) in colors.into_iter().enumerate() {
                self.px[area.top_left.y as usize][x] = c;
            }
            Ok(())
        }
    }
    let scene = Scene::<I16F16>::parse(include_str!("../scenes/paper-program1.scene")).unwrap();
    let mut t = Rows {
        fills: 0,
        px: [[Rgb888::BLACK; 6]; 4],
    };
    let r = Renderer::new(&scene, 6, 4).with_samples(3);
    render_with(&r, &mut t).unwrap();
    assert_eq!(t.fills, 4);
    // Rows rendered alone, in reverse order, give the same pixels.
    for row in (0..4).rev() {
        let mut out = [Rgb888::BLACK; 6];
        r.render_row(row, &mut out);
        assert_eq!(out, t.px[row as usize]);
    }
}

/// Evaluates SPEC section 4 in f64 for a sphere at depth `z` seen head-on by
/// the centre pixel: hit point (0, 0, z + 1), normal +z, viewer +z.
fn shade_head_on(
    ka: [f64; 3],
    kd: [f64; 3],
    ks: [f64; 3],
    shine: f64,
    ia: [f64; 3],
    light: [f64; 3],
    z: f64,
) -> [f64; 3] {
    let p = [0.0, 0.0, z + 1.0];
    let l = [light[0] - p[0], light[1] - p[1], light[2] - p[2]];
    let len = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    let l = l.map(|x| x / len);
    let n_dot_l = l[2];
    let r = [
        2.0 * n_dot_l * 0.0 - l[0],
        2.0 * n_dot_l * 0.0 - l[1],
        2.0 * n_dot_l - l[2],
    ];
    let r_dot_v = r[2].max(0.0);
    [0, 1, 2].map(|i| ka[i] * ia[i] + kd[i] * n_dot_l.max(0.0) + ks[i] * r_dot_v.powf(shine))
}

#[test]
fn phong_shading_matches_the_spec_formula() {
    let text = "ambient_light 0.5 0.25 1\nlight_position 1 2 0\nobject sphere\nKa 0.2 0.4 0.1\nKd 0.3 0.5 0.2\nKs 0.6 0.3 0.2\nshine 7.5\ntranslate 0 0 -8\n";
    let want = shade_head_on(
        [0.2, 0.4, 0.1],
        [0.3, 0.5, 0.2],
        [0.6, 0.3, 0.2],
        7.5,
        [0.5, 0.25, 1.0],
        [1.0, 2.0, 0.0],
        -8.0,
    );
    fn centre<S: Scalar>(text: &str) -> [f64; 3] {
        let scene = Scene::<S>::parse(text).unwrap();
        Renderer::new(&scene, 9, 9).pixel_rays(4, 4).0.to_f64()
    }
    for got in [centre::<f32>(text), centre::<I16F16>(text)] {
        for i in 0..3 {
            assert!((got[i] - want[i]).abs() < 2e-3, "{got:?} vs {want:?}");
        }
    }
    // And the 8-bit value is round(255 v).
    let scene = Scene::<f32>::parse(text).unwrap();
    let px = Renderer::new(&scene, 9, 9).pixel(4, 4);
    assert_eq!(px.r(), (255.0 * want[0].min(1.0)).round() as u8);
}

#[test]
fn light_behind_the_surface_adds_nothing_and_shadows_block() {
    // Light behind the sphere: only ambient remains.
    let text =
        "ambient_light 1 1 1\nlight_position 0 0 -20\nobject sphere\nKa 0.1 0.1 0.1\nKs 1 1 1\ntranslate 0 0 -8\n";
    let scene = Scene::<I16F16>::parse(text).unwrap();
    assert_eq!(Renderer::new(&scene, 9, 9).pixel(4, 4), Rgb888::new(26, 26, 26));
    // A floor lit from above, with a sphere between: shadowed only with shadows on.
    let floor = "light_position 0 10 -8\nobject plane\nKa 0 0 0\nKd 1 1 1\nrotate x -90\ntranslate 0 -2 0\nobject sphere\nKa 0 0 0\nKd 0 0 0\ntranslate 0 0 -8\n";
    let lit = Scene::<I16F16>::parse(floor).unwrap();
    let shadowed = Scene::<I16F16>::parse(&format!("shadows on\n{floor}")).unwrap();
    // 40x30 pixels, p = 0.25, H = 3.75: pixel (20, 22) looks along
    // (0.125, -1.875, -8) and meets the floor at depth 8.53, under the sphere.
    let under = |s: &Scene<I16F16>| Renderer::new(s, 40, 30).pixel(20, 22);
    assert!(under(&lit).g() > 100, "lit floor {:?}", under(&lit));
    assert_eq!(under(&shadowed), Rgb888::BLACK);
}

#[test]
fn background_and_checkerboard() {
    let scene = Scene::<I16F16>::parse("background 0 0.5 1\n").unwrap();
    assert_eq!(Renderer::new(&scene, 3, 3).pixel(1, 1), Rgb888::new(0, 128, 255));
    // A plane facing the camera with squares of side 1: neighbouring squares
    // differ by the quarter factor on Ka and Kd.
    let text = "width 8\nimage_distance 8\nambient_light 1 1 1\nobject plane\nKa 0.8 0.8 0.8\nKd 0 0 0\ntexture 1\ntranslate 0 0 -8\n";
    fn corner<S: Scalar>(text: &str) -> [Rgb888; 4] {
        let scene = Scene::<S>::parse(text).unwrap();
        let r = Renderer::new(&scene, 8, 8);
        [r.pixel(0, 0), r.pixel(1, 0), r.pixel(0, 1), r.pixel(1, 1)]
    }
    let fixed = corner::<I16F16>(text);
    // Same again in f32: the image must agree exactly here.
    let float = corner::<f32>(text);
    for px in [fixed, float] {
        // Pixel (0,0) is at film (-3.5, 3.5): square (-4, 3), sum -1: odd, dark.
        assert_eq!(px[0], Rgb888::new(51, 51, 51));
        assert_eq!(px[1], Rgb888::new(204, 204, 204));
        assert_eq!(px[2], Rgb888::new(204, 204, 204));
        assert_eq!(px[3], Rgb888::new(51, 51, 51));
    }
}

#[test]
fn pinhole_ignores_the_sample_count_and_lens_blurs() {
    let base = include_str!("../scenes/paper-program1.scene");
    let pin = |extra: &str| {
        let s = Scene::<I16F16>::parse(&format!("{base}\n{extra}\n")).unwrap();
        let r = Renderer::new(&s, 32, 24);
        (0..24)
            .flat_map(move |y| (0..32).map(move |x| (x, y)))
            .map(|(x, y)| r.pixel(x, y))
            .collect::<std::vec::Vec<_>>()
    };
    assert_eq!(pin("radius 0\npoint 1"), pin("radius 0\npoint 9"));
    assert_ne!(pin("radius 0"), pin("radius 0.4\npoint 9"));
}

#[test]
fn fixed_levels_by_one_multiply_are_exact() {
    use crate::number::Kernels;
    use fixed::types::I16F16;
    for bits in (-70_000i32..20_000_000)
        .step_by(97)
        .chain([0, 1, 65535, 65536, 257 << 16, i32::MAX, i32::MIN])
    {
        let x = I16F16::from_bits(bits);
        // ⌊255 v⌋ exactly (the generic Q16.16 product would saturate at 32767).
        let exact = ((bits as i64 * 255) >> 16).clamp(0, 65535) as u32;
        assert_eq!(x.to_level(), exact, "bits {bits}");
    }
}

#[test]
fn parse_and_bake_errors_are_core_errors() {
    let parse: std::boxed::Box<dyn core::error::Error> = Scene::<I16F16>::parse("object teapot\n").unwrap_err().into();
    assert!(parse.to_string().starts_with("line 1: "), "{parse}");
    let bake: std::boxed::Box<dyn core::error::Error> = crate::bytes::BakeError::ForeignMagic.into();
    assert!(bake.to_string().contains("LRBK"), "{bake}");
}

#[test]
fn checker_cells_are_the_exact_floor_of_x_over_the_side() {
    // Against floor(x / side) in f64 for the exact side: Q16.16's cell may differ
    // only where x lies within 2^-28 relative of a border (the held reciprocal).
    let mut next = crate::test_rng::xorshift32(0x2545_F491);
    for side in [0.3, 0.5181, 1.0, 2.0, 2.5, 6.4387, 9.0, 100.0] {
        let (held, scale) = (
            I16F16::from_num(side),
            <I16F16 as crate::number::Kernels>::checker_scale(side),
        );
        for _ in 0..20_000 {
            let x = I16F16::from_bits((next() as i32) >> (next() % 8));
            let q = x.to_num::<f64>() / side;
            let cell = <I16F16 as crate::number::Kernels>::checker_cell(x, held, scale);
            let tol = q.abs() * 4e-9 + 1e-12;
            assert!(
                cell as f64 <= q + tol && q - tol < (cell + 1) as f64,
                "side {side} x {x}: {cell} vs {q}"
            );
        }
        // A point exactly on a border belongs to the cell above it.
        let on = I16F16::from_num(3.0 * held.to_num::<f64>());
        if side.log2().fract() == 0.0 {
            assert_eq!(
                <I16F16 as crate::number::Kernels>::checker_cell(on, held, scale),
                3,
                "side {side}"
            );
        }
    }
}

#[test]
fn large_lit_objects_do_not_shadow_themselves() {
    // Big objects lit at grazing angles: with shadows on, no pixel may be darker
    // than with shadows off (nothing else is in the scene to cast a shadow).
    let lights = ["300 40 -180", "-250 200 -100", "0 290 -170", "280 -60 -150"];
    for (shape, light) in ["sphere", "cylinder", "cone", "cube"]
        .into_iter()
        .flat_map(|s| lights.map(move |l| (s, l)))
    {
        let text = |shadows: &str| {
            std::format!(
                "width 10\nimage_distance 8\nambient_light 0.1 0.1 0.1\nshadows {shadows}\n\
                 light_position {light}\nlight_intensity 1 1 1\n\
                 object {shape}\nKd 0.9 0.9 0.9\nrotate x 23\nrotate y 31\nscale 15 12 15\ntranslate 20 -10 -150\n"
            )
        };
        let on = Scene::<I16F16>::parse(&text("on")).unwrap();
        let off = Scene::<I16F16>::parse(&text("off")).unwrap();
        let (a, b) = (Renderer::new(&on, 64, 48), Renderer::new(&off, 64, 48));
        for y in 0..48 {
            for x in 0..64 {
                assert_eq!(a.pixel(x, y), b.pixel(x, y), "{shape} {light} ({x}, {y})");
            }
        }
    }
}

#[test]
fn plane_hits_beyond_the_range_are_drawn() {
    // An eye 1000 above an endless floor: the rows just under the horizon lie
    // 32768 or more away; Q16.16 must draw the floor wherever f32 does.
    let text = "width 10\nimage_distance 8\nlens_position 0 1000 0\nlook 0 0 -1\nambient_light 1 1 1\n\
                object plane\nKa 0.5 0.5 0.5\nKd 0 0 0\nrotate x -90\n";
    let fixed = Scene::<I16F16>::parse(text).unwrap();
    let float = Scene::<f32>::parse(text).unwrap();
    let (a, b) = (Renderer::new(&fixed, 160, 120), Renderer::new(&float, 160, 120));
    let mut far = 0;
    for y in 0..120 {
        let floor = |r: &Renderer<'_, f32>| r.pixel(80, y) != Rgb888::new(0, 0, 0);
        if floor(&b) {
            assert_ne!(a.pixel(80, y), Rgb888::new(0, 0, 0), "row {y}");
            far += 1;
        }
    }
    assert!(far > 0);
}

/// A channel's fine value rounds to its 8-bit level exactly as `to_u8`
/// does, in both number types, at every Q16.16 value from below black to
/// above white and at each side of every rounding point (what lets a row
/// carry fine values and still yield the pixels it yielded).
#[test]
fn fine_values_round_to_the_same_levels() {
    fn check<S: Scalar>(v: S) {
        assert_eq!(v.to_u8(), ((v.to_fine() as u32 + 128) >> 8) as u8, "{v:?}");
        assert!(v.to_fine() <= 255 << 8, "{v:?}");
    }
    for bits in -1000..(1 << 16) + 1000 {
        let q = I16F16::from_bits(bits);
        check(q);
        check(q.to_num::<f32>());
    }
    for level in 0..255u32 {
        let half = (level as f32 + 0.5) / 255.0;
        for v in [
            half,
            f32::from_bits(half.to_bits() - 1),
            f32::from_bits(half.to_bits() + 1),
        ] {
            check(v);
        }
    }
    check(f32::NAN);
    check(f32::INFINITY);
}
