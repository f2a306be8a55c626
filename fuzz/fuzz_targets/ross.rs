//! Fuzz target: see [`rubsim_fuzz::ross`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| rubsim_fuzz::ross(data));
