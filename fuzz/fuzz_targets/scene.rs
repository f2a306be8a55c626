//! Fuzz target: see [`rubsim_fuzz::scene`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| rubsim_fuzz::scene(data));
