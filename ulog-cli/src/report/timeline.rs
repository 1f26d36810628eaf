//! Flight modes and marked instants on the page's time axis: the bands and marks
//! behind every plot. What they are (modes, arming, takeoffs, landings, diagnostics)
//! comes from the library's flight analysis ([`super::analysis::timeline`]), the one
//! source `ulog analyze` reads too.

use serde::Serialize;

/// A flight mode from one time to another (seconds since the log's start).
#[derive(Debug, Serialize)]
pub struct ModeBand {
    /// Start.
    pub t0: f64,
    /// End.
    pub t1: f64,
    /// `nav_state`.
    pub mode: u8,
    /// Its name.
    pub name: String,
}

/// A marked instant: arming, takeoff, a logged error, a diagnostic.
#[derive(Debug, Serialize)]
pub struct Mark {
    /// Seconds since the log's start.
    pub t: f64,
    /// `arm`, `disarm`, `takeoff`, `landing`, `error`, `diagnostic`.
    pub kind: &'static str,
    /// What to show.
    pub text: String,
}
