//! A horizontal bar chart as a PNG, for the plots of BENCHMARKS.md
//! (`scripts/bench.sh` draws the boards' instructions a pixel with it):
//!
//! `bar_chart OUT.png TITLE SERIES[,SERIES...] LABEL=V[,V...]...`
//!
//! One group of bars a label, one bar a series in the order given, each with
//! its value at its end; a value of `-` leaves its bar out. The bars share
//! one linear scale from 0.
use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyle};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{PrimitiveStyle, Rectangle};
use embedded_graphics::text::Text;
use lensray_host::{encode, write_atomic, Format, Image};

const COLOURS: [Rgb888; 4] = [
    Rgb888::new(20, 80, 220),
    Rgb888::new(230, 120, 20),
    Rgb888::new(120, 120, 120),
    Rgb888::new(30, 160, 60),
];

fn usage() -> ! {
    eprintln!("usage: bar_chart OUT.png TITLE SERIES[,SERIES...] LABEL=V[,V...]...");
    std::process::exit(2);
}

/// 25902 -> "25,902".
fn grouped(v: f64) -> String {
    let digits = format!("{:.0}", v);
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        usage();
    }
    let (out, title) = (&args[0], &args[1]);
    let series: Vec<&str> = args[2].split(',').collect();
    let groups: Vec<(&str, Vec<Option<f64>>)> = args[3..]
        .iter()
        .map(|g| {
            let (label, values) = g.split_once('=').unwrap_or_else(|| usage());
            let values = values
                .split(',')
                .map(|v| {
                    if v == "-" {
                        None
                    } else {
                        Some(v.parse().unwrap_or_else(|_| usage()))
                    }
                })
                .collect();
            (label, values)
        })
        .collect();
    let max = groups
        .iter()
        .flat_map(|g| g.1.iter().flatten())
        .fold(0.0f64, |a, &b| a.max(b));
    if max <= 0.0 {
        usage();
    }

    let (label_w, bars_w, value_w) = (170i32, 400i32, 60i32);
    let (bar_h, gap, top) = (14i32, 10i32, 44i32);
    let group_h = bar_h * series.len() as i32 + gap;
    let width = (label_w + bars_w + value_w) as u32;
    let height = (top + group_h * groups.len() as i32 + 4) as u32;
    let mut img = Image::filled(width, height, Rgb888::WHITE);
    let ink = MonoTextStyle::new(&FONT_6X10, Rgb888::BLACK);
    let _ = Text::new(title, Point::new(8, 14), ink).draw(&mut img);
    let mut x = 8;
    for (i, s) in series.iter().enumerate() {
        let _ = Rectangle::new(Point::new(x, 22), Size::new(10, 10))
            .into_styled(PrimitiveStyle::with_fill(COLOURS[i % COLOURS.len()]))
            .draw(&mut img);
        let _ = Text::new(s, Point::new(x + 14, 31), ink).draw(&mut img);
        x += 14 + 6 * s.len() as i32 + 16;
    }
    for (g, (label, values)) in groups.iter().enumerate() {
        let y0 = top + g as i32 * group_h;
        let mid = y0 + bar_h * series.len() as i32 / 2 + 4;
        let _ = Text::new(label, Point::new(8, mid), ink).draw(&mut img);
        for (i, v) in values.iter().enumerate() {
            let Some(v) = v else { continue };
            let y = y0 + i as i32 * bar_h;
            let w = ((v / max) * bars_w as f64).round().max(1.0) as u32;
            let _ = Rectangle::new(Point::new(label_w, y), Size::new(w, bar_h as u32 - 2))
                .into_styled(PrimitiveStyle::with_fill(COLOURS[i % COLOURS.len()]))
                .draw(&mut img);
            let _ = Text::new(&grouped(*v), Point::new(label_w + w as i32 + 4, y + 10), ink).draw(&mut img);
        }
    }
    let axis = PrimitiveStyle::with_stroke(Rgb888::BLACK, 1);
    let _ = Rectangle::new(
        Point::new(label_w - 1, top - 2),
        Size::new(1, (height as i32 - top) as u32),
    )
    .into_styled(axis)
    .draw(&mut img);
    let png = encode(&img, Format::Png).unwrap_or_else(|e| {
        eprintln!("bar_chart: {e}");
        std::process::exit(1)
    });
    write_atomic(std::path::Path::new(out), &png).unwrap_or_else(|e| {
        eprintln!("bar_chart: {out}: {e}");
        std::process::exit(1)
    });
    eprintln!("wrote {out}");
}
