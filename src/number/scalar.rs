//! The number trait [`Scalar`] and the sealed machinery behind it
//! ([`Kernels`]), with [`BakeScalar`] for the baked form. Declarations only:
//! the Q16.16 implementation is in `fixed`, the `f32` one in `float`.

mod sealed {
    pub trait Sealed {}
    impl Sealed for fixed::types::I16F16 {}
    impl Sealed for f32 {}
}

/// The number type of a renderer: Q16.16 [`I16F16`](fixed::types::I16F16) or `f32`.
///
/// See the module docs of `number` (`src/number/mod.rs`) for the rules all implementations follow.
pub trait Scalar: Copy + PartialOrd + core::fmt::Debug + Send + Sync + sealed::Sealed + Kernels + 'static {
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// The largest finite value; "no hit yet" and saturated results.
    const MAX: Self;
    /// Smallest ray parameter that counts as a hit (about 2⁻¹⁰ world units):
    /// keeps a reflected or shadow ray from hitting the surface it left.
    const HIT_EPSILON: Self;
    /// Short human name of the number type ("Q16.16", "f32").
    const NAME: &'static str;
    /// Rounds an `f64` to the nearest value of this type, saturating. Set-up only.
    fn from_f64(x: f64) -> Self;
    /// The exact value as `f64` (for tests and reports; never on the per-ray path).
    fn to_f64(self) -> f64;
    /// Converts a small integer exactly (|i| < 32768 for Q16.16; saturates beyond).
    fn from_i32(i: i32) -> Self;
    /// Converts a Q1.15 lens-sample coordinate `i / 32768` exactly.
    fn from_q15(i: i32) -> Self;

    /// `self + o`, saturating.
    fn add(self, o: Self) -> Self;
    /// `self - o`, saturating.
    fn sub(self, o: Self) -> Self;
    /// `self * o`, rounded to nearest, saturating.
    fn mul(self, o: Self) -> Self;
    /// `self / o`, saturating; division by zero saturates (0 / 0 = 0).
    fn div(self, o: Self) -> Self;
    /// `-self`, saturating.
    fn neg(self) -> Self;
    /// `|self|`, saturating.
    fn abs(self) -> Self;
    /// Square root; 0 for negative input. Correctly rounded for `f32`,
    /// within one unit in the last place for Q16.16.
    fn sqrt(self) -> Self;
    /// `self ^ e` for a base in [0, 1] and an exponent `e >= 0`
    /// (the Phong power); `0 ^ 0 = 1`.
    fn powf(self, e: Self) -> Self;
    /// The largest integer not above `self`.
    fn floor_i32(self) -> i32;

    /// `min(self, o)`.
    #[inline]
    fn min(self, o: Self) -> Self {
        if o < self {
            o
        } else {
            self
        }
    }
    /// `max(self, o)`.
    #[inline]
    fn max(self, o: Self) -> Self {
        if o > self {
            o
        } else {
            self
        }
    }
}

/// Sealed: `Kernels` is public in a private module, so outside the crate it
/// can be neither named nor implemented (heapless's `LenType` pattern).
mod kernels {
    use crate::number::film::FilmMapDesc;

    /// The machinery behind [`Scalar`]: exact matrix rows, precise directions,
    /// the film map and the plane, accumulators. Sealed (its module is private),
    /// so it can change without breaking the public trait.
    pub trait Kernels: Copy + Sized {
        /// `Scalar::mul` expanded in place: for the vector operators on the
        /// per-ray path (a call there costs more than the product on the M0).
        fn mul_inline(self, o: Self) -> Self;
        /// `self.mul_inline(1/4)` (a dark checker square's colour), the same value.
        fn quarter(self) -> Self;
        /// Whether a shadow ray leaving the lit side of a convex object skips
        /// that object: Q16.16's absolute rounding at a large object's magnitude
        /// outgrows any fixed offset (f32's relative rounding does not; its
        /// images stay as they were).
        const SHADOW_SKIPS_OWN_CONVEX: bool;
        /// Whether a shadow ray meets bounded shapes along its exact vector to
        /// the light rather than its rounded unit direction (Q16.16: 2⁻¹⁷ of
        /// direction, 150 units on, moved a small blocker's shadow edge by a
        /// pixel). f32 keeps the unit direction; its images stay as they were.
        const SHADOW_PRECISE_DIR: bool;
        /// Whether a bounded shape's object-space origin is the linear part
        /// applied to the ray's offset from the object's centre (f32: the
        /// offset is small where the world coordinates are not, so it keeps
        /// the bits a re-origin at 60 units and a translation of 190 lose).
        const LOCAL_FROM_CENTRE: bool = false;

        /// The checker's scale for a square side `side` (> 0), as
        /// [`Kernels::checker_cell`] takes it: `1 / side` by default. Set-up only.
        fn checker_scale(side: f64) -> Self;

        /// The checker cell index along one axis, `floor(x / side)`, with `side`
        /// the square side in `Self` and `scale` from [`Kernels::checker_scale`].
        fn checker_cell(x: Self, side: Self, scale: Self) -> i64;

        /// As [`Kernels::checker_cell`], with where `x` lies in its cell: a
        /// fraction in [0, 1) (the bits below the cell index; box-filtered checkers).
        fn checker_pos(x: Self, side: Self, scale: Self) -> (i64, Self);

        /// [`Kernels::checker_cell`], and whether `x` may lie on the other side
        /// of a border than the exact hit (within 2⁻¹⁰ object units of one:
        /// Q16.16's rounded point; never for f32, whose images stay as they
        /// were). `on_face`: `x` is a flat face's own coordinate (the hit's
        /// normal along this axis), exact: never in doubt.
        fn checker_near(x: Self, side: Self, scale: Self, _on_face: bool) -> (i64, bool) {
            (Self::checker_cell(x, side, scale), false)
        }

        /// One row of an affine matrix, stored more precisely than `Self`
        /// (Q16.16 keeps up to 30 fraction bits; see `Kernels::row_from_f64`).
        type Row: Copy + core::fmt::Debug + Send + Sync;
        /// Accumulator for sums of many colours (a pixel's samples).
        type Acc: Copy + core::fmt::Debug + Send + Sync;

        /// Length of a 3-vector, computed without intermediate overflow.
        fn length3(v: [Self; 3]) -> Self;
        /// Unit vector along `v`, and the length of `v`. A zero vector gives zero.
        fn normalize3(v: [Self; 3]) -> ([Self; 3], Self);
        /// `|v|² <= r²`, decided exactly (no intermediate overflow).
        fn within(v: [Self; 3], r: Self) -> bool;
        /// `a · b > 0`, decided exactly for Q16.16 (no rounding, no saturation).
        fn dot_positive(a: [Self; 3], b: [Self; 3]) -> bool;

        /// Builds a matrix row `(a, b, c, t)` from its exact `f64` entries.
        fn row_from_f64(r: [f64; 4]) -> Self::Row;
        /// `a·x + b·y + c·z (+ t if affine)`, with one rounding at the end.
        fn row_apply(row: &Self::Row, v: [Self; 3], affine: bool) -> Self;
        /// The row's linear entry `j` (0 to 2: `a`, `b`, `c`), rounded to `Self`.
        fn row_entry(row: &Self::Row, j: usize) -> Self;
        /// The row `(a, b, c, t)` exactly as held, in `f64`. Set-up only.
        fn row_to_f64(row: &Self::Row) -> [f64; 4];

        /// The direction `M v` for the three rows of a matrix, as a unit vector
        /// with its length `|M v|` and, where that is below 1, the reciprocal
        /// `1 / |M v|` (0 otherwise), all from the exact product: a large scale
        /// (rows of 1/2000) keeps its precision, where rounding `M v` to `Self`
        /// first would leave it a few bits. A zero result gives zeros.
        fn rows_apply_unit(rows: &[Self::Row; 3], v: [Self; 3]) -> ([Self; 3], Self, Self);

        /// A ray direction held more precisely than three `Self` values (Q16.16:
        /// 31-bit mantissas with a shared power of two), for the unbounded plane,
        /// whose hits along a grazing ray move by the ray's direction error times
        /// the square of the distance.
        type Dir: Copy + core::fmt::Debug + PartialEq + Send + Sync;
        /// A vector as a precise direction, exactly.
        fn dir_from(v: [Self; 3]) -> Self::Dir;
        /// The ray's origin's bits below `Self` where the precise direction
        /// carries them for the centre-relative origin (`LOCAL_FROM_CENTRE`, f32).
        fn origin_low(_d: &Self::Dir) -> Option<[Self; 3]> {
            None
        }
        /// A camera's exact map from pixels to its rays' directions (see [`crate::number::film`]).
        type FilmMap: Copy + core::fmt::Debug + Send + Sync;
        /// A pixel's chief direction as the film map gives it, before the lens.
        type Film: Copy + core::fmt::Debug + PartialEq + Send + Sync;
        /// Rounds a film map's exact parts. Set-up only.
        fn film_map(desc: &FilmMapDesc) -> Self::FilmMap;
        /// The chief direction `D(i, j)` of the doubled pixel centre (i, j).
        fn film_dir(map: &Self::FilmMap, i: i32, j: i32) -> Self::Film;
        /// `film_dir(map, i + 2, j)` from `film = film_dir(map, i, j)`, the
        /// pixel to its right: the same value, where a type can step to it.
        #[inline]
        fn film_dir_right(map: &Self::FilmMap, _film: &Self::Film, i: i32, j: i32) -> Self::Film {
            Self::film_dir(map, i + 2, j)
        }
        /// The unit direction along the film direction tilted by a lens sample
        /// (Q1.15; (0, 0) for the chief ray): precise, marked unit, and rounded.
        fn film_ray_dir(map: &Self::FilmMap, film: &Self::Film, lens: (i32, i32)) -> (Self::Dir, [Self; 3]);
        /// Where the world ray `o + t d` meets the object-space plane z = 0 of an
        /// object whose world → object matrix has these rows, for `t_min < t < t_max`:
        /// `(t, x, y)`, t the world distance in units of |d| (a unit direction
        /// marked so needs no square root) and (x, y, 0) the object-space point.
        /// `checker` is the plane's texture (side, scale) as
        /// [`Kernels::checker_cell`] takes them (side 0: none): for a hit beyond
        /// the type's range, x and y may come back as another point of the true
        /// hit's checker parity (Q16.16; a plane's x and y serve only its texture).
        /// `face` `(axis, ±1)` meets instead the plane where object coordinate
        /// `axis` is ±1 (a cube's face met at grazing; `eye` then `None`):
        /// `(2, 0)` for the plane itself.
        #[allow(clippy::too_many_arguments)]
        fn plane_hit(
            rows: &[Self::Row; 3],
            o: [Self; 3],
            d: Self::Dir,
            t_min: Self,
            t_max: Self,
            checker: (Self, Self),
            eye: Option<[Self; 4]>,
            face: (usize, i8),
        ) -> Option<(Self, Self, Self)>;

        /// What [`Kernels::plane_hit`] computes from the origin alone, for a
        /// ray from the pinhole `eye` (world, exact): given back to it as `eye`
        /// for every chief ray (the same bits, once a frame). `None` where the
        /// type has no such shortcut (f32). Set-up only.
        fn plane_from_eye(_rows: &[Self::Row; 3], _eye: [f64; 3]) -> Option<[Self; 4]> {
            None
        }

        /// [`Kernels::rows_apply_unit`] for a precise direction marked unit (a
        /// camera ray's), from its mantissas: `None` where the type keeps the
        /// rounded unit direction (f32; a direction not marked unit).
        fn rows_apply_dir(_rows: &[Self::Row; 3], _d: &Self::Dir) -> Option<([Self; 3], Self, Self)> {
            None
        }
        /// The point `o + t D` for a precise direction marked unit, from its
        /// mantissas (one rounding): `None` as for [`Kernels::rows_apply_dir`].
        fn along_dir(_o: [Self; 3], _d: &Self::Dir, _t: Self) -> Option<[Self; 3]> {
            None
        }

        /// The roots `(t0, t1)` of the cylinder's (`cone` false) or the cone's
        /// side quadric along the object-space ray `o + t d`, where the type
        /// computes them exactly (Q16.16: `number::quadric`): `Some(None)` for
        /// no root. `None`: the shape's generic quadratic (f32, unchanged).
        fn side_roots(_o: [Self; 3], _d: [Self; 3], _cone: bool, _close: &mut bool) -> Option<Option<(Self, Self)>> {
            None
        }

        /// Whether a bounded shape's decision found close to its boundary is
        /// decided again from an object-space ray rounded once at the ray's
        /// closest approach ([`Kernels::exact_point`]): Q16.16, whose ray,
        /// re-origined then transformed, holds 2⁻¹⁷ a component times the
        /// object's inverse scale. f32 keeps its images.
        const RECHECK: bool = false;

        /// The object-space point `rows · (o + s d)` of a world ray `o + s d`
        /// (`d` as held precisely), computed exactly and rounded once, and
        /// with `rim` (a unit direction) whether the line through the exact
        /// point along it meets the unit sphere, with `solid` (`q16::CUBE`,
        /// `CYLINDER`, `CONE`) whether the ray meets that solid and through
        /// which face or part; `None` where the type has no such kernel (f32)
        /// or the scales do not fit.
        fn exact_point(
            _rows: &[Self::Row; 3],
            _o: [Self; 3],
            _d: &Self::Dir,
            _s: Self,
            _rim: Option<[Self; 3]>,
            _solid: u8,
        ) -> Option<([Self; 3], crate::number::q16::Decided)> {
            None
        }

        /// The sum of the checker's cells over the three axes of a hit
        /// (object-space point and normal `hit`) on the `surface`
        /// (`q16::FLAT`, `ROUND`, `CYLINDER`, `CONE`) of the world ray
        /// `o + s d`, from the exact ray (`q16::exact_cells`): where
        /// [`Kernels::checker_near`] finds a border close. `None` where the
        /// type has no such kernel (f32) or the scales do not fit.
        #[allow(clippy::too_many_arguments)]
        fn exact_cells(
            _rows: &[Self::Row; 3],
            _o: [Self; 3],
            _d: &Self::Dir,
            _s: Self,
            _hit: ([Self; 3], [Self; 3]),
            _surface: u8,
            _checker: (Self, Self),
        ) -> Option<i64> {
            None
        }

        /// A hit's world distance along the world ray `o + s d` taken again
        /// from the exact ray (`q16::exact_t`), at 2^-30 world units: `hit`
        /// its object-space point and normal on the `surface` (as in
        /// [`Kernels::exact_cells`]), `s` its rounded distance. Where two
        /// objects' hits lie within a few steps of each other, the nearer is
        /// decided on it. `None` where the type has no such kernel (f32,
        /// whose order stays as it was) or the scales do not fit.
        fn exact_t(
            _rows: &[Self::Row; 3],
            _o: [Self; 3],
            _d: &Self::Dir,
            _s: Self,
            _hit: ([Self; 3], [Self; 3]),
            _surface: u8,
        ) -> Option<i64> {
            None
        }

        /// The point `o + t d` of the world ray (`d` held precisely) at its
        /// exact distance `t` (at 2^-30 world units, from
        /// [`Kernels::exact_t`]), rounded once (`q16::exact_hit_point`).
        /// `None` where the type has no such kernel (f32) or the scales do
        /// not fit.
        fn exact_hit_point(_o: [Self; 3], _d: &Self::Dir, _t: i64) -> Option<[Self; 3]> {
            None
        }

        /// A shadow ray's line taken again from the exact hit
        /// (`q16::shadow_line`): the world ray `o + t d` (`d` held precisely)
        /// hit at `t` (at 2^-30 world units, from [`Kernels::exact_t`]), the
        /// start `P + n ε` and the direction `light − (P + n ε)` from the exact `P`,
        /// as the start rounded to `Self` and a precise direction carrying its
        /// bits below. `None` where the type has no such kernel (f32, whose
        /// shadow rays stay as they were) or the scales do not fit.
        fn shadow_line(
            _o: [Self; 3],
            _d: &Self::Dir,
            _t: i64,
            _offset: ([Self; 3], Self),
            _light: [Self; 3],
        ) -> Option<([Self; 3], Self::Dir)> {
            None
        }

        /// The empty accumulator.
        fn acc_zero() -> Self::Acc;
        /// `acc + x`.
        fn acc_add(acc: Self::Acc, x: Self) -> Self::Acc;
        /// `acc / n`, saturating (n > 0).
        fn acc_mean(acc: Self::Acc, n: u32) -> Self;

        /// A colour channel clamped to [0, 1] and rounded to 8 bits: `round(255 v)`.
        fn to_u8(self) -> u8;

        /// A colour channel clamped to [0, 1] in 256ths of an 8-bit level,
        /// truncated: `⌊256 · 255 v⌋` (f32: of its rounded `255 v + ½`, less
        /// 128), so that [`Kernels::to_u8`] is exactly `(to_fine + 128) >> 8`
        /// (what gaps interpolate: see [`crate::render::scanline::Fine`]).
        fn to_fine(self) -> u16;

        /// A colour channel in 8-bit levels, unclamped above white: `⌊255 v⌋`
        /// clamped to 0..=65535 (what adaptive sampling's statistics count).
        fn to_level(self) -> u32;
    }
}
pub(crate) use kernels::Kernels;

/// A number type whose renderers can be baked: [`I16F16`](fixed::types::I16F16) and `f32`. Its
/// matrix rows and film map have baked forms too.
pub trait BakeScalar:
    Scalar<Row = <Self as BakeScalar>::BakedRow, FilmMap = <Self as BakeScalar>::BakedFilmMap> + crate::bytes::Field
{
    /// The number type's tag in the header: 0 Q16.16, 1 f32.
    const TAG: u8;
    /// `Kernels::Row`.
    type BakedRow: crate::bytes::Field + Copy + core::fmt::Debug + Send + Sync;
    /// `Kernels::FilmMap`.
    type BakedFilmMap: crate::bytes::Field + Copy + core::fmt::Debug + Send + Sync;
    /// Whether the film map's integer kernels stay in range for this image size.
    fn film_map_fits(map: &Self::BakedFilmMap, cols: u32, rows: u32) -> bool;
}
