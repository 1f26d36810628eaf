//! The format-string grammar and layout resolution on arbitrary text: a format that
//! parses prints back to text that parses to the same format, and laying out a set of
//! arbitrary formats never panics and stays within the limits.
#![no_main]

use libfuzzer_sys::fuzz_target;
use ulog_format::{Format, Limits, Resolver};

fuzz_target!(|texts: Vec<&str>| {
    let mut formats = Vec::new();
    for t in &texts {
        match Format::parse_all(t) {
            Ok(f) => {
                let again = Format::parse(&f.to_string()).expect("printed format parses");
                assert_eq!(again.name, f.name);
                assert_eq!(again.fields.len(), f.fields.len());
                formats.push(f);
            }
            Err(errors) => {
                assert!(!errors.is_empty());
                for e in errors {
                    assert!(e.span.start <= t.len());
                }
            }
        }
    }
    let limits = Limits::default();
    let mut r = Resolver::new(limits);
    for f in &formats {
        if let Ok(l) = r.resolve(&f.name, &formats) {
            assert!(l.size() <= limits.max_size);
            assert!(l.min_size() <= l.size());
            if l.size() <= 4096 {
                for leaf in l.leaves() {
                    assert!(leaf.offset + leaf.count * leaf.ty.size() <= l.size());
                    let _ = l.find(&leaf.path);
                }
            }
        }
    }
});
