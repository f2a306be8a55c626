//! Fuzz target: see [`rubsim_fuzz::msh`].
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| rubsim_fuzz::msh(data));
