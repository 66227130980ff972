//! The unit tests' one random source: xorshift32, seeded, so a failure replays.

/// Marsaglia's xorshift32 from `seed` (not 0): the raw 32-bit words.
pub(crate) fn xorshift32(mut seed: u32) -> impl FnMut() -> u32 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed
    }
}

/// The same words as uniform values in [0, 1].
pub(crate) fn unit_f64(seed: u32) -> impl FnMut() -> f64 {
    let mut next = xorshift32(seed);
    move || next() as f64 / u32::MAX as f64
}
