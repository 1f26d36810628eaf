//! Wall-clock time: what a log says of the UTC time of its boot-relative timestamps.

use std::fmt;

use ulog_format::{BasicType, LayoutType};

use crate::definitions::timestamp::Unwrapper;
use crate::definitions::Subscription;
use crate::log::ulog::ULog;

/// The GPS topics that carry the receiver's UTC time (`time_utc_usec`), in the order
/// they are tried: the vehicle's selected receiver, then the raw receivers (instance
/// 0), then the topic newer PX4 names the selected one.
const GPS_TOPICS: [&str; 3] = ["vehicle_gps_position", "sensor_gps", "vehicle_gnss"];

/// The UTC times taken as a receiver's or a clock's, 2010-01-01 to 2100-01-01: before
/// a fix receivers report zero (PX4 then logs 0) or their firmware's build date, and
/// a damaged value can be anything.
const PLAUSIBLE_UTC_US: std::ops::Range<u64> = 1_262_304_000_000_000..4_102_444_800_000_000;

/// Where a log's UTC time comes from ([`ULog::utc`]).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum UtcSource {
    /// The GPS receiver's time: the median over the rows of `topic` (instance 0)
    /// of `time_utc_usec − timestamp`, over the `samples` rows with a plausible time.
    /// The median, not the first fix: a receiver's first times can be off by the
    /// leap seconds until it has the almanac.
    Gps {
        /// The topic the time was read from.
        topic: &'static str,
        /// The rows with a time that went into the median.
        samples: usize,
    },
    /// Information key `boot_time_utc_us` (PX4 v1.15 and later): the autopilot's
    /// clock at boot, as set when the log started.
    BootTime,
}

impl fmt::Display for UtcSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UtcSource::Gps { topic, samples } => {
                write!(f, "GPS time ({topic}.time_utc_usec, {samples} samples)")
            }
            UtcSource::BootTime => f.write_str("information key boot_time_utc_us"),
        }
    }
}

/// The UTC time of a log's timestamps: the time at boot, with where it comes from.
///
/// ```
/// use ulog_core::read::UtcClock;
/// let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// // The sample log has no GPS and no `boot_time_utc_us`: no UTC time.
/// assert!(log.utc().is_none());
/// let clock = UtcClock::from_boot(1_707_236_822_000_000);
/// assert_eq!(clock.at(1_500_000).to_string(), "2024-02-06T16:27:03.500000Z");
/// assert_eq!(format!("{:.0}", clock.at(0)), "2024-02-06T16:27:02Z");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UtcClock {
    boot_us: i64,
    source: UtcSource,
}

impl UtcClock {
    /// A clock whose boot (timestamp 0) was at `boot_us` microseconds since the Unix
    /// epoch, as information key `boot_time_utc_us` gives it.
    pub fn from_boot(boot_us: i64) -> UtcClock {
        UtcClock {
            boot_us,
            source: UtcSource::BootTime,
        }
    }

    /// The UTC time of boot-relative `timestamp` (microseconds).
    pub fn at(&self, timestamp: u64) -> UtcTime {
        UtcTime(
            self.boot_us
                .saturating_add(timestamp.min(i64::MAX as u64) as i64),
        )
    }

    /// Microseconds since the Unix epoch at boot (timestamp 0).
    pub fn boot_us(&self) -> i64 {
        self.boot_us
    }

    /// Where the time comes from.
    pub fn source(&self) -> &UtcSource {
        &self.source
    }
}

/// A UTC time in microseconds since the Unix epoch. Displayed in RFC 3339 with the
/// microseconds (`2024-02-06T16:27:02.123456Z`); a precision gives fewer digits of the
/// second (`{:.3}` milliseconds, `{:.0}` none), truncated, not rounded, so that a time
/// never prints in the next second.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct UtcTime(pub i64);

impl UtcTime {
    /// Microseconds since the Unix epoch.
    pub fn micros(self) -> i64 {
        self.0
    }
}

impl fmt::Display for UtcTime {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let secs = self.0.div_euclid(1_000_000);
        let micros = self.0.rem_euclid(1_000_000);
        let (days, rest) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
        let (y, m, d) = civil_from_days(days);
        write!(
            f,
            "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}",
            rest / 3600,
            rest / 60 % 60,
            rest % 60
        )?;
        let digits = f.precision().unwrap_or(6).min(6);
        if digits > 0 {
            let fraction = micros / 10i64.pow(6 - digits as u32);
            write!(f, ".{fraction:0digits$}")?;
        }
        f.write_str("Z")
    }
}

/// The proleptic Gregorian date of `days` since 1970-01-01: the days are counted in
/// 400-year eras of 146 097 days, each starting on a 1 March so that the leap day is
/// the last day of its year.
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468; // days from 0000-03-01 to 1970-01-01
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_from_march = (5 * day_of_year + 2) / 153;
    let day = (day_of_year - (153 * month_from_march + 2) / 5 + 1) as u32;
    let month = if month_from_march < 10 {
        month_from_march + 3
    } else {
        month_from_march - 9
    } as u32;
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

impl ULog<'_> {
    /// The UTC time of this log's timestamps, if the log says it. In this order:
    ///
    /// 1. the GPS receiver's time ([`UtcSource::Gps`]): `time_utc_usec` of
    ///    `vehicle_gps_position`, else `sensor_gps`, else `vehicle_gnss` (instance 0),
    ///    the median of its offset to `timestamp` over the rows with a time; a
    ///    receiver's time is the one a log's own clock was not needed for;
    /// 2. information key `boot_time_utc_us` of newer PX4 ([`UtcSource::BootTime`]):
    ///    the autopilot's clock at boot, right when the clock was set (from a GPS, a
    ///    companion computer or a ground station) before the log started.
    ///
    /// Information key `time_ref_utc`, which PX4 also writes, is not a time: it is the
    /// offset of the local time zone in seconds (parameter `SDLOG_UTC_OFFSET`), used
    /// to name log files.
    pub fn utc(&self) -> Option<UtcClock> {
        GPS_TOPICS
            .iter()
            .find_map(|topic| self.gps_clock(topic))
            .or_else(|| self.boot_clock())
    }

    /// The clock of information key `boot_time_utc_us`, when it is a plausible time.
    pub(crate) fn boot_clock(&self) -> Option<UtcClock> {
        let boot = self.info_value("boot_time_utc_us")?.as_u64()?;
        PLAUSIBLE_UTC_US
            .contains(&boot)
            .then(|| UtcClock::from_boot(boot as i64))
    }

    fn gps_clock(&self, topic: &'static str) -> Option<UtcClock> {
        let t = self.topic(topic, 0).ok()?;
        let utc = t.field("time_utc_usec").ok()?;
        let mut timestamps = Unwrapper::new(t.timestamp_field());
        let offsets: Vec<i64> = t
            .payloads()
            .filter_map(|p| gps_offset(timestamps.push(p)?, utc.read(p)?.as_u64()?))
            .collect();
        median_clock(topic, offsets)
    }
}

/// The offset of a GPS time to its row's timestamp, if the time is plausible.
fn gps_offset(timestamp: u64, utc: u64) -> Option<i64> {
    let offset = i64::try_from(utc).ok()? - i64::try_from(timestamp).ok()?;
    PLAUSIBLE_UTC_US.contains(&utc).then_some(offset)
}

/// The clock of the median of a GPS topic's offsets; `None` when there are none.
fn median_clock(topic: &'static str, mut offsets: Vec<i64>) -> Option<UtcClock> {
    if offsets.is_empty() {
        return None;
    }
    let mid = offsets.len() / 2;
    let (_, &mut median, _) = offsets.select_nth_unstable(mid);
    Some(UtcClock {
        boot_us: median,
        source: UtcSource::Gps {
            topic,
            samples: offsets.len(),
        },
    })
}

/// [`ULog::utc`] of a log read in one pass that does not keep its data
/// ([`LogMetadata`](crate::read::LogMetadata)'s): the GPS offsets are taken as the
/// rows go by, 8 bytes a row.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct UtcSamples {
    /// The offsets of each of [`GPS_TOPICS`], instance 0.
    offsets: [Vec<i64>; 3],
    /// Whether a subscription of each was met.
    claimed: [bool; 3],
}

/// Where a GPS topic's time is: its rank in [`GPS_TOPICS`] and the offset of its
/// `uint64_t time_utc_usec` in a payload.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GpsTime {
    rank: usize,
    offset: usize,
}

impl UtcSamples {
    /// Where the GPS time of `sub`'s rows is, if it is one of [`GPS_TOPICS`], instance
    /// 0, and the first subscription of its name met (the rows of a second one are not
    /// taken).
    pub(crate) fn gps_time(&mut self, sub: &Subscription) -> Option<GpsTime> {
        let rank = GPS_TOPICS.iter().position(|t| *t == sub.name())?;
        if sub.multi_id() != 0 || std::mem::replace(&mut self.claimed[rank], true) {
            return None;
        }
        let field = sub.layout().ok()?.find("time_utc_usec")?;
        (matches!(field.ty, LayoutType::Basic(BasicType::UInt64)) && !field.is_array).then_some(
            GpsTime {
                rank,
                offset: field.offset,
            },
        )
    }

    /// Takes the time of a row of the topic at `at` whose timestamp is `timestamp`.
    pub(crate) fn push(&mut self, at: GpsTime, payload: &[u8], timestamp: u64) {
        let Some(bytes) = payload.get(at.offset..at.offset + 8) else {
            return;
        };
        let mut utc = [0u8; 8];
        utc.copy_from_slice(bytes);
        if let Some(offset) = gps_offset(timestamp, u64::from_le_bytes(utc)) {
            self.offsets[at.rank].push(offset);
        }
    }

    /// The clock by [`ULog::utc`]'s rule, `boot` giving the clock of the log's
    /// information when no GPS time is there.
    pub(crate) fn clock(&self, boot: impl FnOnce() -> Option<UtcClock>) -> Option<UtcClock> {
        GPS_TOPICS
            .iter()
            .zip(&self.offsets)
            .find_map(|(topic, offsets)| median_clock(topic, offsets.clone()))
            .or_else(boot)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::LogBuilder;

    #[test]
    fn dates_are_the_calendars() {
        let cases = [
            (0, "1970-01-01T00:00:00.000000Z"),
            (-1, "1969-12-31T23:59:59.999999Z"),
            (951_782_400_000_000, "2000-02-29T00:00:00.000000Z"),
            (1_707_236_822_123_456, "2024-02-06T16:27:02.123456Z"),
            (4_107_542_399_999_999, "2100-02-28T23:59:59.999999Z"),
            (4_107_542_400_000_000, "2100-03-01T00:00:00.000000Z"),
        ];
        for (us, text) in cases {
            assert_eq!(UtcTime(us).to_string(), text, "{us}");
        }
        assert_eq!(
            format!("{:.3}", UtcTime(1_707_236_822_123_999)),
            "2024-02-06T16:27:02.123Z"
        );
        // Every day of four centuries maps to the next date.
        let mut last = civil_from_days(-1);
        for day in 0..146_097 {
            let next = civil_from_days(day);
            let (y, m, d) = last;
            let expected = if next.2 == 1 {
                if m == 12 {
                    (y + 1, 1, 1)
                } else {
                    (y, m + 1, 1)
                }
            } else {
                (y, m, d + 1)
            };
            assert_eq!(next, expected, "day {day}");
            let leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
            let days_in = [
                31,
                if leap { 29 } else { 28 },
                31,
                30,
                31,
                30,
                31,
                31,
                30,
                31,
                30,
                31,
            ];
            if next.2 == 1 {
                assert_eq!(d, days_in[m as usize - 1], "end of {y}-{m}");
            }
            last = next;
        }
    }

    fn gps_log(rows: &[(u64, u64)], boot_info: Option<u64>) -> Vec<u8> {
        let mut b = LogBuilder::new(1, 0);
        if let Some(v) = boot_info {
            b.info("uint64_t boot_time_utc_us", &v.to_le_bytes());
        }
        b.format("vehicle_gps_position:uint64_t timestamp;uint64_t time_utc_usec;uint8_t fix_type;uint8_t[7] _padding0;");
        b.subscribe(0, 1, "vehicle_gps_position");
        for &(t, utc) in rows {
            let mut p = t.to_le_bytes().to_vec();
            p.extend_from_slice(&utc.to_le_bytes());
            p.extend_from_slice(&[3, 0, 0, 0, 0, 0, 0, 0]);
            b.data(1, &p);
        }
        b.into_bytes()
    }

    #[test]
    fn gps_time_is_the_median_offset_of_rows_with_a_time() {
        let boot = 1_707_236_822_000_000u64;
        // No time yet, one 18 s off (leap seconds), three right to within jitter.
        let rows = [
            (1_000_000, 0),
            (2_000_000, boot + 2_000_000 - 18_000_000),
            (3_000_000, boot + 3_000_100),
            (4_000_000, boot + 4_000_050),
            (5_000_000, boot + 5_000_070),
        ];
        let bytes = gps_log(&rows, Some(boot - 5_000_000));
        let log = ULog::parse(&bytes).unwrap();
        let clock = log.utc().unwrap();
        assert_eq!(
            clock.source(),
            &UtcSource::Gps {
                topic: "vehicle_gps_position",
                samples: 4
            }
        );
        assert_eq!(clock.boot_us(), boot as i64 + 70);
        assert_eq!(clock.at(0).micros(), boot as i64 + 70);
    }

    #[test]
    fn boot_time_information_when_no_gps_has_a_time() {
        let boot = 1_707_236_822_000_000u64;
        let bytes = gps_log(&[(1_000_000, 0)], Some(boot));
        let log = ULog::parse(&bytes).unwrap();
        let clock = log.utc().unwrap();
        assert_eq!(clock.source(), &UtcSource::BootTime);
        assert_eq!(clock.at(2).micros(), boot as i64 + 2);
        let bytes = gps_log(&[(1_000_000, 0)], None);
        assert_eq!(ULog::parse(&bytes).unwrap().utc(), None);
    }
}
