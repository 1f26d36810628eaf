//! Benchmarks of `ulog-core` live in `benches/benches/` (`cargo bench -p
//! ulog-benches`); `-- --test` runs each once, for CI.
