//! The standard PX4 plots of a report, as Flight Review draws them: which topics and
//! fields each line comes from, under the names of old (2016) and new (2024) firmware.

/// Radians to degrees.
const DEG: f32 = 180.0 / core::f32::consts::PI;

/// One plot: its lines come from one or more groups (a topic each).
pub struct PlotSpec {
    /// The plot's id in the page (and the tests).
    pub id: &'static str,
    /// The plot's heading.
    pub title: &'static str,
    /// The unit of its y axis.
    pub unit: &'static str,
    /// Where its lines come from.
    pub groups: &'static [Group],
    /// Whether lines that are zero throughout are left out (unused outputs).
    pub drop_zero: bool,
}

/// Lines read from one topic: the first of `topics` the log has (its lowest instance).
pub struct Group {
    /// Candidate topics, newest name first.
    pub topics: &'static [&'static str],
    /// The lines.
    pub lines: &'static [Line],
}

/// One line of a plot.
pub struct Line {
    /// Its name in the legend.
    pub label: &'static str,
    /// How its value is made of the topic's fields.
    pub value: Value,
}

/// How a line's value is made.
pub enum Value {
    /// The first of these fields the topic has, times the factor.
    Field(&'static [(&'static str, f32)]),
    /// The length of the vector of these three fields (the first triple the topic
    /// has).
    Norm(&'static [[&'static str; 3]]),
}

const fn field(label: &'static str, fields: &'static [(&'static str, f32)]) -> Line {
    Line {
        label,
        value: Value::Field(fields),
    }
}

const GPS: &[&str] = &["vehicle_gps_position", "sensor_gps"];

/// The standard plots, in page order. Attitude (from quaternions, through typed
/// bindings) and the GPS track are drawn by their own code.
pub const PLOTS: &[PlotSpec] = &[
    PlotSpec {
        id: "altitude",
        title: "Altitude",
        unit: "m",
        drop_zero: false,
        groups: &[
            Group {
                topics: &["vehicle_air_data", "sensor_combined"],
                lines: &[field("barometer", &[("baro_alt_meter", 1.0)])],
            },
            Group {
                topics: GPS,
                lines: &[field("GPS", &[("altitude_msl_m", 1.0), ("alt", 1e-3)])],
            },
            Group {
                topics: &["vehicle_global_position"],
                lines: &[field("fused", &[("alt", 1.0)])],
            },
            Group {
                topics: &["position_setpoint_triplet"],
                lines: &[field("setpoint", &[("current.alt", 1.0)])],
            },
        ],
    },
    PlotSpec {
        id: "rates",
        title: "Angular rates",
        unit: "deg/s",
        drop_zero: false,
        groups: &[
            Group {
                topics: &["vehicle_angular_velocity", "vehicle_attitude"],
                lines: &[
                    field("roll rate", &[("xyz[0]", DEG), ("rollspeed", DEG)]),
                    field("pitch rate", &[("xyz[1]", DEG), ("pitchspeed", DEG)]),
                    field("yaw rate", &[("xyz[2]", DEG), ("yawspeed", DEG)]),
                ],
            },
            Group {
                topics: &["vehicle_rates_setpoint"],
                lines: &[
                    field("roll rate setpoint", &[("roll", DEG)]),
                    field("pitch rate setpoint", &[("pitch", DEG)]),
                    field("yaw rate setpoint", &[("yaw", DEG)]),
                ],
            },
        ],
    },
    PlotSpec {
        id: "position",
        title: "Local position",
        unit: "m",
        drop_zero: false,
        groups: &[
            Group {
                topics: &["vehicle_local_position"],
                lines: &[
                    field("x (north)", &[("x", 1.0)]),
                    field("y (east)", &[("y", 1.0)]),
                    field("z (down)", &[("z", 1.0)]),
                ],
            },
            Group {
                topics: &["vehicle_local_position_setpoint"],
                lines: &[
                    field("x setpoint", &[("x", 1.0)]),
                    field("y setpoint", &[("y", 1.0)]),
                    field("z setpoint", &[("z", 1.0)]),
                ],
            },
        ],
    },
    PlotSpec {
        id: "velocity",
        title: "Velocity",
        unit: "m/s",
        drop_zero: false,
        groups: &[
            Group {
                topics: &["vehicle_local_position"],
                lines: &[
                    field("vx", &[("vx", 1.0)]),
                    field("vy", &[("vy", 1.0)]),
                    field("vz", &[("vz", 1.0)]),
                ],
            },
            Group {
                topics: &["vehicle_local_position_setpoint"],
                lines: &[
                    field("vx setpoint", &[("vx", 1.0)]),
                    field("vy setpoint", &[("vy", 1.0)]),
                    field("vz setpoint", &[("vz", 1.0)]),
                ],
            },
        ],
    },
    PlotSpec {
        id: "manual",
        title: "Manual control inputs",
        unit: "",
        drop_zero: false,
        groups: &[Group {
            topics: &["manual_control_setpoint"],
            // Before 2023: x pitch, y roll, z throttle, r yaw.
            lines: &[
                field("roll", &[("roll", 1.0), ("y", 1.0)]),
                field("pitch", &[("pitch", 1.0), ("x", 1.0)]),
                field("yaw", &[("yaw", 1.0), ("r", 1.0)]),
                field("throttle", &[("throttle", 1.0), ("z", 1.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "controls",
        title: "Actuator controls",
        unit: "",
        drop_zero: false,
        groups: &[
            Group {
                topics: &["actuator_controls_0"],
                lines: &[
                    field("roll", &[("control[0]", 1.0)]),
                    field("pitch", &[("control[1]", 1.0)]),
                    field("yaw", &[("control[2]", 1.0)]),
                    field("thrust", &[("control[3]", 1.0)]),
                ],
            },
            Group {
                topics: &["vehicle_torque_setpoint"],
                lines: &[
                    field("roll torque", &[("xyz[0]", 1.0)]),
                    field("pitch torque", &[("xyz[1]", 1.0)]),
                    field("yaw torque", &[("xyz[2]", 1.0)]),
                ],
            },
            Group {
                topics: &["vehicle_thrust_setpoint"],
                lines: &[field("thrust (z)", &[("xyz[2]", 1.0)])],
            },
        ],
    },
    PlotSpec {
        id: "motors",
        title: "Motors (normalised)",
        unit: "",
        drop_zero: true,
        groups: &[Group {
            topics: &["actuator_motors"],
            lines: &[
                field("motor 1", &[("control[0]", 1.0)]),
                field("motor 2", &[("control[1]", 1.0)]),
                field("motor 3", &[("control[2]", 1.0)]),
                field("motor 4", &[("control[3]", 1.0)]),
                field("motor 5", &[("control[4]", 1.0)]),
                field("motor 6", &[("control[5]", 1.0)]),
                field("motor 7", &[("control[6]", 1.0)]),
                field("motor 8", &[("control[7]", 1.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "outputs",
        title: "Actuator outputs (motors and servos)",
        unit: "",
        drop_zero: true,
        groups: &[Group {
            topics: &["actuator_outputs"],
            lines: &[
                field("output 1", &[("output[0]", 1.0)]),
                field("output 2", &[("output[1]", 1.0)]),
                field("output 3", &[("output[2]", 1.0)]),
                field("output 4", &[("output[3]", 1.0)]),
                field("output 5", &[("output[4]", 1.0)]),
                field("output 6", &[("output[5]", 1.0)]),
                field("output 7", &[("output[6]", 1.0)]),
                field("output 8", &[("output[7]", 1.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "accel",
        title: "Raw acceleration",
        unit: "m/s²",
        drop_zero: false,
        groups: &[Group {
            topics: &["sensor_combined"],
            lines: &[
                field("x", &[("accelerometer_m_s2[0]", 1.0)]),
                field("y", &[("accelerometer_m_s2[1]", 1.0)]),
                field("z", &[("accelerometer_m_s2[2]", 1.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "gyro",
        title: "Raw angular speed (gyroscope)",
        unit: "deg/s",
        drop_zero: false,
        groups: &[Group {
            topics: &["sensor_combined"],
            lines: &[
                field("x", &[("gyro_rad[0]", DEG)]),
                field("y", &[("gyro_rad[1]", DEG)]),
                field("z", &[("gyro_rad[2]", DEG)]),
            ],
        }],
    },
    PlotSpec {
        id: "vibration",
        title: "Vibration metrics",
        unit: "",
        drop_zero: false,
        groups: &[
            Group {
                topics: &["vehicle_imu_status"],
                lines: &[
                    field("accel vibration [m/s²]", &[("accel_vibration_metric", 1.0)]),
                    field("gyro vibration [rad/s]", &[("gyro_vibration_metric", 1.0)]),
                    field(
                        "gyro coning [rad²/s]",
                        &[("delta_angle_coning_metric", 1.0)],
                    ),
                ],
            },
            Group {
                topics: &["estimator_status"],
                lines: &[
                    field("gyro coning (vibe[0])", &[("vibe[0]", 1.0)]),
                    field("gyro high-freq (vibe[1])", &[("vibe[1]", 1.0)]),
                    field("accel high-freq (vibe[2])", &[("vibe[2]", 1.0)]),
                ],
            },
        ],
    },
    PlotSpec {
        id: "clipping",
        title: "IMU clipping (counts)",
        unit: "",
        drop_zero: false,
        groups: &[Group {
            topics: &["vehicle_imu_status"],
            lines: &[
                field("accel x", &[("accel_clipping[0]", 1.0)]),
                field("accel y", &[("accel_clipping[1]", 1.0)]),
                field("accel z", &[("accel_clipping[2]", 1.0)]),
                field("gyro x", &[("gyro_clipping[0]", 1.0)]),
                field("gyro y", &[("gyro_clipping[1]", 1.0)]),
                field("gyro z", &[("gyro_clipping[2]", 1.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "battery",
        title: "Battery",
        unit: "V, A, %",
        drop_zero: false,
        groups: &[Group {
            topics: &["battery_status"],
            lines: &[
                field("voltage [V]", &[("voltage_v", 1.0)]),
                field("current [A]", &[("current_a", 1.0)]),
                field("remaining [%]", &[("remaining", 100.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "gps",
        title: "GPS fix, satellites and precision",
        unit: "",
        drop_zero: false,
        groups: &[Group {
            topics: GPS,
            lines: &[
                field("fix type", &[("fix_type", 1.0)]),
                field("satellites", &[("satellites_used", 1.0)]),
                field("eph [m]", &[("eph", 1.0)]),
                field("epv [m]", &[("epv", 1.0)]),
                field("hdop", &[("hdop", 1.0)]),
                field("vdop", &[("vdop", 1.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "gps_noise",
        title: "GPS noise and jamming",
        unit: "",
        drop_zero: false,
        groups: &[Group {
            topics: GPS,
            lines: &[
                field("noise per ms", &[("noise_per_ms", 1.0)]),
                field("jamming indicator", &[("jamming_indicator", 1.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "test_ratios",
        title: "Estimator test ratios",
        unit: "",
        drop_zero: false,
        groups: &[Group {
            topics: &["estimator_status"],
            lines: &[
                field("magnetometer", &[("mag_test_ratio", 1.0)]),
                field("velocity", &[("vel_test_ratio", 1.0)]),
                field("position", &[("pos_test_ratio", 1.0)]),
                field("height", &[("hgt_test_ratio", 1.0)]),
                field("airspeed", &[("tas_test_ratio", 1.0)]),
                field("height above ground", &[("hagl_test_ratio", 1.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "load",
        title: "CPU and RAM load",
        unit: "%",
        drop_zero: false,
        groups: &[Group {
            topics: &["cpuload"],
            lines: &[
                field("CPU", &[("load", 100.0)]),
                field("RAM", &[("ram_usage", 100.0)]),
            ],
        }],
    },
    PlotSpec {
        id: "mag",
        title: "Magnetic field norm",
        unit: "Ga",
        drop_zero: false,
        groups: &[Group {
            topics: &["vehicle_magnetometer", "sensor_combined"],
            lines: &[Line {
                label: "|B|",
                value: Value::Norm(&[[
                    "magnetometer_ga[0]",
                    "magnetometer_ga[1]",
                    "magnetometer_ga[2]",
                ]]),
            }],
        }],
    },
];
