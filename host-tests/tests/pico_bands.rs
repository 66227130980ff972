//! The Pico's two-core row sharing (`firmware/pico/src/bands.rs`, compiled
//! here as it is): bands recorded by either of two renderers and drawn in any
//! order that keeps the passes in order (the one rule `two_cores.rs` keeps)
//! give exactly the plain render, for scenes and sizes drawn at random.

#[path = "../../firmware/pico/src/bands.rs"]
#[allow(dead_code)]
mod bands;

use bands::{Bands, Recorder, Shadow};
use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::*;
use lensray::progressive::{render_pass_row, Schedule};
use lensray::{render_with, Renderer, Scene, I16F16};
use lensray_testkit::fuzz::{scene_from_grammar, Rng};

/// A random scene the parser accepts (the fuzzer's grammar), or Program 1.
fn scene(rng: &mut Rng) -> Scene<I16F16> {
    for _ in 0..200 {
        if let Ok(s) = Scene::parse_bytes(&scene_from_grammar(rng)) {
            return s;
        }
    }
    Scene::parse(include_str!("../../scenes/paper-program1.scene")).unwrap()
}

/// A panel that counts the windows drawn: `fill_solid` and `fill_contiguous` calls.
struct Counting<'a> {
    panel: &'a mut MockDisplay<Rgb565>,
    windows: usize,
}

impl Dimensions for Counting<'_> {
    fn bounding_box(&self) -> embedded_graphics::primitives::Rectangle {
        self.panel.bounding_box()
    }
}

impl DrawTarget for Counting<'_> {
    type Color = Rgb565;
    type Error = core::convert::Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
        self.panel.draw_iter(pixels)
    }
    fn fill_solid(&mut self, area: &embedded_graphics::primitives::Rectangle, c: Rgb565) -> Result<(), Self::Error> {
        self.windows += 1;
        self.panel.fill_solid(area, c)
    }
    fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
        &mut self,
        area: &embedded_graphics::primitives::Rectangle,
        colours: I,
    ) -> Result<(), Self::Error> {
        self.windows += 1;
        self.panel.fill_contiguous(area, colours)
    }
}

#[test]
fn bands_from_two_renderers_in_any_pass_ordered_interleaving_equal_the_plain_render() {
    let mut rng = Rng::new(0x9160_2040);
    for case in 0..40 {
        let s = scene(&mut rng);
        // MockDisplay is 64x64: sizes up to that, odd ones included.
        let (w, h) = (1 + rng.below(64) as u32, 1 + rng.below(64) as u32);
        let samples = 1 + rng.below(3) as u32;
        let renderer = Renderer::new(&s, w, h).with_samples(samples);
        let first_step = 1 << rng.below(4);
        let bands = Bands::new(Schedule::new(first_step, 1, samples), h);

        // Each band recorded on its own, as whichever core takes it records it.
        let size = Size::new(w, h);
        let mut recorded: Vec<(usize, Recorder)> = (0..bands.len())
            .map(|k| {
                let band = bands.get(k).unwrap();
                let mut rec = Recorder::new(size);
                render_pass_row(&renderer, &mut rec, &band.pass, band.row).expect("a band fits the recorder");
                (band.pass_index, rec)
            })
            .collect();
        assert!(bands.get(bands.len()).is_none());
        // Within a pass, any order: shuffle each pass's bands.
        for i in (1..recorded.len()).rev() {
            let j = rng.below(i + 1);
            recorded.swap(i, j);
        }
        recorded.sort_by_key(|(pass, _)| *pass); // stable: the shuffle stays within each pass

        let mut panel = MockDisplay::<Rgb565>::new();
        panel.set_allow_overdraw(true);
        let mut shadow = Box::new(Shadow::new(w));
        let mut counting = Counting {
            panel: &mut panel,
            windows: 0,
        };
        for (_, rec) in &recorded {
            rec.replay(&mut counting, &mut shadow).unwrap();
        }
        // Each band one window (none if it skipped every block), its skipped blocks sent again from the shadow.
        let drawn = recorded.iter().filter(|(_, rec)| !rec.is_empty()).count();
        assert_eq!(counting.windows, drawn, "case {case}");
        let mut plain = MockDisplay::<Rgb565>::new();
        render_with(&renderer, &mut plain).unwrap();
        assert_eq!(
            panel, plain,
            "case {case}: {w}x{h}, {samples} samples, first step {first_step}"
        );
    }
}

#[test]
fn drawing_a_later_pass_first_would_show() {
    // The pass order matters (so the rule above is needed, and the test can fail).
    let s = Scene::<I16F16>::parse(include_str!("../../scenes/paper-program1.scene")).unwrap();
    let renderer = Renderer::new(&s, 32, 24).with_samples(1);
    let bands = Bands::new(Schedule::new(8, 1, 1), 24);
    let mut panel = MockDisplay::<Rgb565>::new();
    panel.set_allow_overdraw(true);
    let mut shadow = Box::new(Shadow::new(32));
    for k in (0..bands.len()).rev() {
        let band = bands.get(k).unwrap();
        let mut rec = Recorder::new(Size::new(32, 24));
        render_pass_row(&renderer, &mut rec, &band.pass, band.row).unwrap();
        rec.replay(&mut panel, &mut shadow).unwrap();
    }
    let mut plain = MockDisplay::<Rgb565>::new();
    render_with(&renderer, &mut plain).unwrap();
    assert_ne!(panel, plain);
}

#[test]
fn the_recorder_refuses_what_it_cannot_replay() {
    let mut rec = Recorder::new(Size::new(8, 8));
    assert!(Pixel(Point::new(1, 1), Rgb565::RED).draw(&mut rec).is_err());
    let row = embedded_graphics::primitives::Rectangle::new(Point::zero(), Size::new(4, 1));
    assert!(rec.fill_contiguous(&row, [Rgb565::RED; 3]).is_err(), "too few colours");
    assert!(rec.fill_contiguous(&row, [Rgb565::RED; 4]).is_ok());
    assert!(
        rec.fill_contiguous(&row, [Rgb565::RED; 4]).is_err(),
        "a second run in one band"
    );
}
