//! Typed decoding against arbitrary formats: a binding planned against whatever
//! layout the input describes either matches (then decodes any payload of a valid
//! length without panicking) or reports the differences.
#![no_main]

use libfuzzer_sys::fuzz_target;
use ulog_core::typed::{CharArray, Plan};
use ulog_core::ULogMessage;
use ulog_format::{Format, Layout};

#[derive(ULogMessage, Debug)]
#[ulog(name = "fuzzed")]
struct Binding {
    timestamp: u64,
    #[ulog(alias = "value")]
    x: f32,
    flags: [bool; 2],
    name: CharArray<4>,
    inner: Inner2,
    _padding0: [u8; 3],
}

#[derive(ULogMessage, Debug)]
#[ulog(name = "inner")]
struct Inner2 {
    a: i16,
    b: [u8; 3],
}

fuzz_target!(|input: (Vec<&str>, Vec<u8>)| {
    let (texts, payload) = input;
    let formats: Vec<Format> = texts.iter().filter_map(|t| Format::parse(t).ok()).collect();
    let Ok(layout) = Layout::resolve("fuzzed", &formats[..]) else {
        return;
    };
    let _ = Plan::<Inner2>::new(&layout);
    match Plan::<Binding>::new(&layout) {
        Ok(plan) => {
            let r = plan.decode(&payload);
            assert_eq!(r.is_ok(), layout.accepts_len(payload.len()));
            let mut full = payload.clone();
            full.resize(layout.size(), 0);
            assert!(plan.decode(&full).is_ok());
        }
        Err(m) => assert!(!m.differences.is_empty()),
    }
});
