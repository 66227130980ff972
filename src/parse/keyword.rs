//! The scene format's keywords, written once: one table gives the
//! [`Keyword`] enum, each keyword's word, how many values it takes and which
//! part of a scene it belongs to. The parser looks words up here and the
//! host fuzzers and their dictionary are derived from it.

/// Which part of a scene a statement belongs to.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Section {
    /// Camera, lens, sampling and whole-scene statements.
    Camera,
    /// A point light.
    Light,
    /// The statement that starts an object.
    Object,
    /// A property of the current object.
    Property,
    /// A transformation of the current object.
    Transform,
}

/// Generates [`Keyword`] with its word, arity and section from one table.
macro_rules! keywords {
    ($( $variant:ident = $name:literal, $arity:literal, $section:ident; )*) => {
        /// A statement's keyword.
        #[derive(Copy, Clone, Debug, PartialEq, Eq)]
        pub enum Keyword {
            $(
                #[doc = concat!("`", $name, "`")]
                $variant,
            )*
        }

        impl Keyword {
            /// Every keyword, in the table's order.
            pub const ALL: [Keyword; [$($name),*].len()] = [$(Keyword::$variant),*];

            /// The word written in a scene.
            pub const fn name(self) -> &'static str {
                match self { $(Keyword::$variant => $name,)* }
            }

            /// How many values the statement takes at most (a shape,
            /// material, axis or switch word counts as one).
            pub const fn arity(self) -> usize {
                match self { $(Keyword::$variant => $arity,)* }
            }

            /// The part of a scene the statement belongs to.
            pub const fn section(self) -> Section {
                match self { $(Keyword::$variant => Section::$section,)* }
            }

            /// The keyword written `word`, if the format has one.
            pub fn from_name(word: &str) -> Option<Keyword> {
                match word {
                    $($name => Some(Keyword::$variant),)*
                    _ => None,
                }
            }
        }
    };
}

keywords! {
    FocusDistance = "focus_distance", 1, Camera;
    FNumber = "f_number", 1, Camera;
    FocusOn = "focus_on", 1, Camera;
    ApertureBlades = "aperture_blades", 1, Camera;
    ApertureRotation = "aperture_rotation", 1, Camera;
    Width = "width", 1, Camera;
    AspectRatio = "aspect_ratio", 1, Camera;
    ImageDistance = "image_distance", 1, Camera;
    LensPosition = "lens_position", 3, Camera;
    FocalLength = "focal_length", 1, Camera;
    Look = "look", 3, Camera;
    Up = "up", 3, Camera;
    Point = "point", 1, Camera;
    Radius = "radius", 1, Camera;
    AmbientLight = "ambient_light", 3, Camera;
    LightPosition = "light_position", 3, Light;
    LightIntensity = "light_intensity", 3, Light;
    Background = "background", 3, Camera;
    Shadows = "shadows", 1, Camera;
    Adaptive = "adaptive", 1, Camera;
    Sampler = "sampler", 1, Camera;
    Object = "object", 2, Object;
    Ka = "Ka", 3, Property;
    Kd = "Kd", 3, Property;
    Ks = "Ks", 3, Property;
    Shine = "shine", 1, Property;
    Texture = "texture", 1, Property;
    TotalTransformation = "total_transformation", 1, Property;
    Scale = "scale", 3, Transform;
    Rotate = "rotate", 2, Transform;
    Translate = "translate", 3, Transform;
}

/// Every keyword's word, in the table's order.
pub const KEYWORDS: [&str; Keyword::ALL.len()] = {
    let mut out = [""; Keyword::ALL.len()];
    let mut i = 0;
    while i < out.len() {
        out[i] = Keyword::ALL[i].name();
        i += 1;
    }
    out
};

/// The axes `rotate` turns about, in order x, y, z.
pub const AXES: [&str; 3] = ["x", "y", "z"];

/// The values of an on/off switch (`shadows`, `adaptive`): off, then on.
pub const SWITCH: [&str; 2] = ["off", "on"];

/// The lens samplers' words (`sampler`), in [`crate::camera::sampler::Sampler`]'s order.
pub const SAMPLERS: [&str; 2] = ["independent", "stratified"];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::shape::Shape;
    use crate::scene::MATERIALS;
    use crate::{Scene, I16F16};
    use std::format;
    use std::string::String;
    use std::vec::Vec;

    /// Value `i` of a well-formed statement of `k`, from the format's own word lists.
    fn value(k: Keyword, i: usize) -> &'static str {
        match (k, i) {
            (Keyword::Object, 0) => Shape::ALL[0].0,
            (Keyword::Object, _) => MATERIALS[0].0,
            (Keyword::Rotate, 0) => AXES[2],
            (Keyword::Shadows | Keyword::Adaptive, _) => SWITCH[1],
            (Keyword::Sampler, _) => SAMPLERS[0],
            (Keyword::ApertureBlades | Keyword::ImageDistance, _) => "6",
            _ => "1",
        }
    }

    /// A scene with one object and one light around a statement of `k` with `n` values.
    fn scene_with(k: Keyword, n: usize) -> String {
        let values: Vec<&str> = (0..n).map(|i| value(k, i)).collect();
        let st = format!("{} {}", k.name(), values.join(" "));
        match k.section() {
            Section::Camera => format!("{st}\nlight_position 0 5 0\nobject sphere\ntranslate 0 0 -5\n"),
            _ => format!("light_position 0 5 0\nobject sphere\n{st}\ntranslate 0 0 -5\n"),
        }
    }

    #[test]
    fn the_parser_takes_every_keyword_with_its_arity_and_no_more() {
        for k in Keyword::ALL {
            assert_eq!(Keyword::from_name(k.name()), Some(k));
            let text = scene_with(k, k.arity());
            if let Err(e) = Scene::<I16F16>::parse(&text) {
                panic!("{k:?} with {} values: {e}\n{text}", k.arity());
            }
            let extra = scene_with(k, k.arity() + 1);
            assert!(
                Scene::<I16F16>::parse(&extra).is_err(),
                "{k:?} took {} values\n{extra}",
                k.arity() + 1
            );
        }
        assert_eq!(Keyword::from_name("Width"), None);
    }

    /// The dictionary's word entries, from the tables the parser reads.
    fn dictionary_words() -> String {
        let words = KEYWORDS
            .iter()
            .chain(Shape::ALL.iter().map(|(name, _)| name))
            .chain(MATERIALS.iter().map(|m| &m.0))
            .chain(AXES.iter())
            .chain(SWITCH.iter())
            .chain(SAMPLERS.iter());
        words.enumerate().map(|(i, w)| format!("kw{i}=\"{w}\"\n")).collect()
    }

    #[test]
    fn fuzz_dictionary_lists_the_grammar_words() {
        let fuzz = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
        if !fuzz.join("Cargo.toml").is_file() {
            // The published package holds the library alone: the fuzzer and
            // its dictionary are the repository's, checked there.
            return;
        }
        let path = fuzz.join("parse_render.dict");
        let text = std::fs::read_to_string(&path).unwrap();
        // The dictionary: comment lines, the grammar's words (`kw…`), then edge values.
        let keep = |l: &&str| !l.starts_with("kw");
        let head: String = text
            .lines()
            .take_while(|l| l.starts_with('#'))
            .map(|l| format!("{l}\n"))
            .collect();
        let rest: String = text
            .lines()
            .filter(keep)
            .filter(|l| !l.starts_with('#'))
            .map(|l| format!("{l}\n"))
            .collect();
        let want = format!("{head}{}{rest}", dictionary_words());
        if std::env::var_os("LENSRAY_WRITE_DICT").is_some() {
            std::fs::write(&path, &want).unwrap();
        }
        assert!(
            text == want,
            "fuzz/parse_render.dict is not what the keyword table gives; regenerate it with\n\
             LENSRAY_WRITE_DICT=1 cargo test -p lensray --lib fuzz_dictionary"
        );
    }
}
