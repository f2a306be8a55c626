//! Fuzz target: see [`rubsim_fuzz::manifest`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| rubsim_fuzz::manifest(data));
