//! A dataset's tables of the flight analysis ([`crate::analysis`], made in the pass
//! that converts the log): [`ANALYSIS_FILE`], one row per log and diagnostic, and
//! [`FLIGHTS_FILE`], one row per log with its flight statistics.

use std::sync::Arc;

use arrow_array::builder::{Float64Builder, StringBuilder, UInt32Builder, UInt64Builder};
use arrow_array::{ArrayRef, RecordBatch, StringArray};
use arrow_schema::{DataType, Field, Schema, SchemaRef};

use super::error::ExportError;
use crate::analysis::FlightAnalysis;

/// The dataset's table of diagnostics: `log_id`, `id` (`battery_brownout`,
/// `ekf_failure`, `gps_interference`, `motor_failure`, `rc_loss`), `severity`,
/// `timestamp_us`, `end_timestamp_us`, `summary`, `evidence` (a JSON object with its
/// `type`, as `ulog analyze --json` writes it).
pub const ANALYSIS_FILE: &str = "analysis.parquet";
/// The dataset's table of flight statistics, one row per log: `log_id`, `armed_s`,
/// `airborne_s`, `takeoff_us`, the distances, altitudes, speeds, tilt and rotation of
/// [`FlightStats`](crate::analysis::FlightStats), the battery's `battery_*`, the GPS's
/// `gps_*`, the accelerometer's `vibration_mean`, `vibration_max`, `vibration_status`,
/// and the number of `diagnostics` and of `critical` ones.
pub const FLIGHTS_FILE: &str = "flights.parquet";

/// The stats columns, in order, and how each is read from an analysis.
type Stat = (&'static str, fn(&FlightAnalysis) -> Option<f64>);

const STATS: &[Stat] = &[
    ("armed_s", |f| Some(f.timeline.armed_s)),
    ("airborne_s", |f| Some(f.timeline.airborne_s)),
    ("total_distance_m", |f| Some(f.stats.total_distance_m)),
    ("flown_distance_m", |f| Some(f.stats.flown_distance_m)),
    ("max_altitude_diff_m", |f| Some(f.stats.max_altitude_diff_m)),
    ("max_altitude_above_start_m", |f| {
        Some(f.stats.max_altitude_above_start_m)
    }),
    ("max_speed_m_s", |f| Some(f.stats.max_speed_m_s)),
    ("max_horizontal_speed_m_s", |f| {
        Some(f.stats.max_horizontal_speed_m_s)
    }),
    ("max_speed_up_m_s", |f| Some(f.stats.max_speed_up_m_s)),
    ("max_speed_down_m_s", |f| Some(f.stats.max_speed_down_m_s)),
    ("avg_speed_m_s", |f| Some(f.stats.avg_speed_m_s)),
    ("max_tilt_deg", |f| Some(f.stats.max_tilt_deg)),
    ("max_rotation_speed_deg_s", |f| {
        Some(f.stats.max_rotation_speed_deg_s)
    }),
    ("battery_min_voltage_v", |f| f.battery.min_voltage_v),
    ("battery_avg_current_a", |f| f.battery.avg_current_a),
    ("battery_max_current_a", |f| f.battery.max_current_a),
    ("battery_discharged_mah", |f| f.battery.discharged_mah),
    ("gps_min_satellites", |f| {
        f.gps.as_ref()?.min_satellites.map(f64::from)
    }),
    ("gps_max_eph_m", |f| {
        f.gps.as_ref()?.max_eph_m.map(f64::from)
    }),
    ("gps_max_epv_m", |f| {
        f.gps.as_ref()?.max_epv_m.map(f64::from)
    }),
    ("vibration_mean", |f| f.vibration.accel_vibe_mean),
    ("vibration_max", |f| f.vibration.accel_vibe_max),
];

fn field(name: &str, ty: DataType, nullable: bool) -> Field {
    Field::new(name, ty, nullable)
}

/// The two tables: file name and schema.
pub(super) fn tables() -> [(&'static str, SchemaRef); 2] {
    let analysis = Schema::new(vec![
        field("log_id", DataType::Utf8, false),
        field("id", DataType::Utf8, false),
        field("severity", DataType::Utf8, false),
        field("timestamp_us", DataType::UInt64, false),
        field("end_timestamp_us", DataType::UInt64, true),
        field("summary", DataType::Utf8, false),
        field("evidence", DataType::Utf8, false),
    ]);
    let mut flights = vec![field("log_id", DataType::Utf8, false)];
    flights.push(field("takeoff_us", DataType::UInt64, true));
    flights.extend(
        STATS
            .iter()
            .map(|(name, _)| field(name, DataType::Float64, true)),
    );
    flights.push(field("vibration_status", DataType::Utf8, false));
    flights.push(field("diagnostics", DataType::UInt32, false));
    flights.push(field("critical", DataType::UInt32, false));
    [
        (ANALYSIS_FILE, Arc::new(analysis)),
        (FLIGHTS_FILE, Arc::new(Schema::new(flights))),
    ]
}

/// A log's rows of the two tables.
pub(super) fn batches(
    log_id: &str,
    flight: &FlightAnalysis,
) -> Result<[RecordBatch; 2], ExportError> {
    let [(_, analysis), (_, flights)] = tables();
    let ids = |n: usize| -> ArrayRef {
        Arc::new(StringArray::from_iter_values(
            std::iter::repeat(log_id).take(n),
        ))
    };
    let d = &flight.diagnostics;
    let text = |v: Vec<String>| -> ArrayRef { Arc::new(StringArray::from(v)) };
    let mut end = UInt64Builder::new();
    for x in d {
        end.append_option(x.end_timestamp_us);
    }
    let analysis = RecordBatch::try_new(
        analysis,
        vec![
            ids(d.len()),
            text(d.iter().map(|x| x.id.to_owned()).collect()),
            text(d.iter().map(|x| x.severity.as_str().to_owned()).collect()),
            Arc::new(UInt64Builder::new().tap(|b| {
                d.iter().for_each(|x| b.append_value(x.timestamp_us));
            })),
            Arc::new(end.finish()),
            text(d.iter().map(|x| x.summary.clone()).collect()),
            text(d.iter().map(|x| x.evidence.json()).collect()),
        ],
    )
    .map_err(ExportError::encoding)?;
    let mut columns: Vec<ArrayRef> = vec![ids(1)];
    let mut takeoff = UInt64Builder::new();
    takeoff.append_option(flight.timeline.takeoff_us());
    columns.push(Arc::new(takeoff.finish()));
    for (_, read) in STATS {
        let mut b = Float64Builder::new();
        b.append_option(read(flight).filter(|v| v.is_finite()));
        columns.push(Arc::new(b.finish()));
    }
    let mut status = StringBuilder::new();
    status.append_value(flight.vibration.status);
    columns.push(Arc::new(status.finish()));
    let count = |critical: bool| {
        let mut b = UInt32Builder::new();
        let n = d
            .iter()
            .filter(|x| !critical || x.severity == crate::analysis::Severity::Critical)
            .count();
        b.append_value(u32::try_from(n).unwrap_or(u32::MAX));
        Arc::new(b.finish()) as ArrayRef
    };
    columns.push(count(false));
    columns.push(count(true));
    let flights = RecordBatch::try_new(flights, columns).map_err(ExportError::encoding)?;
    Ok([analysis, flights])
}

/// Builds in place, then finishes.
trait Tap: Sized {
    fn tap(self, f: impl FnOnce(&mut Self)) -> arrow_array::UInt64Array;
}

impl Tap for UInt64Builder {
    fn tap(mut self, f: impl FnOnce(&mut Self)) -> arrow_array::UInt64Array {
        f(&mut self);
        self.finish()
    }
}
