//! The analysis functions against signals whose answers are known: sines in noise,
//! chirps, and simulated first- and second-order loops.

use std::f64::consts::PI;

use super::*;
use crate::testing::Rng;

/// A standard normal sample (Box–Muller) from the deterministic generator.
fn gaussian(rng: &mut Rng) -> f64 {
    let u = |rng: &mut Rng| ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let (a, b) = (u(rng), u(rng));
    (-2.0 * a.ln()).sqrt() * (2.0 * PI * b).cos()
}

/// `amplitude · sin(2π f t) + offset` plus white noise of deviation `sigma`.
fn noisy_sine(n: usize, rate: f64, f: f64, amplitude: f64, sigma: f64, seed: u64) -> Vec<f64> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|i| {
            0.3 + amplitude * (2.0 * PI * f * i as f64 / rate).sin() + sigma * gaussian(&mut rng)
        })
        .collect()
}

fn variance(x: &[f64]) -> f64 {
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / x.len() as f64
}

#[test]
fn psd_peaks_at_the_sine_and_integrates_to_the_variance() {
    let (rate, f, amplitude) = (250.0, 37.3, 1.5);
    let x = noisy_sine(25_000, rate, f, amplitude, 0.2, 1);
    let s = psd(&x, rate, &PsdOptions::default()).unwrap();
    assert_eq!(s.frequencies.len(), 129); // 256-sample segments
    let peak = s.dominant_frequencies(3, 10.0);
    assert_eq!(peak.len(), 1, "{peak:?}");
    assert!((peak[0].frequency_hz - f).abs() <= s.resolution_hz());
    // Parseval: the density integrates to the variance (A²/2 + σ²).
    let v = variance(&x);
    assert!(
        (s.integral() - v).abs() / v < 0.03,
        "{} vs {v}",
        s.integral()
    );
    // f32 samples give the same answer.
    let x32: Vec<f32> = x.iter().map(|&v| v as f32).collect();
    let s32 = psd(&x32, rate, &PsdOptions::default()).unwrap();
    assert!((s32.integral() - s.integral()).abs() / v < 1e-4);
}

#[test]
fn psd_of_white_noise_is_flat_at_its_density() {
    // White noise of variance σ² spreads σ²/(rate/2) over the one-sided band.
    let (rate, sigma) = (500.0, 0.5);
    let mut rng = Rng::new(3);
    let x: Vec<f64> = (0..50_000).map(|_| sigma * gaussian(&mut rng)).collect();
    let s = psd(&x, rate, &PsdOptions::default().segment_len(128)).unwrap();
    let expected = sigma * sigma / (rate / 2.0);
    let inner = &s.values[2..s.values.len() - 2];
    let mean = inner.iter().sum::<f64>() / inner.len() as f64;
    assert!(
        (mean - expected).abs() / expected < 0.03,
        "{mean} vs {expected}"
    );
}

#[test]
fn amplitude_spectrum_reads_the_sine_amplitude() {
    // 40 Hz at 400 Hz over 10 s: the tone falls on bin 400.
    let (rate, f, amplitude) = (400.0, 40.0, 0.8);
    let x = noisy_sine(4000, rate, f, amplitude, 0.05, 2);
    let s = amplitude_spectrum(&x, rate).unwrap();
    let k = (f * x.len() as f64 / rate).round() as usize;
    assert_eq!(s.frequencies[k], f);
    assert!(
        (s.values[k] - amplitude).abs() / amplitude < 0.01,
        "{}",
        s.values[k]
    );
    let peak = s.dominant_frequencies(1, 10.0)[0];
    assert_eq!(peak.frequency_hz, f);
    // The mean, in the 0 Hz bin.
    assert!((s.values[0] - 0.3).abs() < 0.01);
}

#[test]
fn spectrogram_of_a_chirp_rises_in_frequency() {
    // 5 Hz → 95 Hz over 20 s at 250 Hz: f(t) = 5 + 4.5 t.
    let rate = 250.0;
    let x: Vec<f64> = (0..5000)
        .map(|i| {
            let t = i as f64 / rate;
            (2.0 * PI * (5.0 * t + 2.25 * t * t)).sin()
        })
        .collect();
    let s = spectrogram(&x, rate, &SpectrogramOptions::default()).unwrap();
    assert_eq!(s.power_db.len(), s.times_s.len());
    let peaks: Vec<f64> = (0..s.times_s.len())
        .map(|t| s.peak_frequency(t).unwrap())
        .collect();
    let bin = s.frequencies[1];
    for (t, (&time, &peak)) in s.times_s.iter().zip(&peaks).enumerate() {
        let expected = 5.0 + 4.5 * time;
        assert!(
            (peak - expected).abs() <= 1.5 * bin,
            "window {t}: {peak} vs {expected}"
        );
    }
    assert!(peaks.windows(2).all(|w| w[1] >= w[0]));
    assert!(peaks.last().unwrap() - peaks[0] > 80.0);
}

/// A setpoint that jumps to a random level in −1..1 and holds it 0.05–0.5 s.
fn random_steps(n: usize, rate: f64, seed: u64) -> Vec<f64> {
    let mut rng = Rng::new(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let level = rng.below(2001) as f64 / 1000.0 - 1.0;
        let hold = ((0.05 + rng.below(451) as f64 / 1000.0) * rate) as usize;
        out.extend(std::iter::repeat(level).take(hold.max(1)));
    }
    out.truncate(n);
    out
}

/// The response of y' = (sp − y)/τ to a setpoint held between samples (exact).
fn first_order(sp: &[f64], rate: f64, tau: f64) -> Vec<f64> {
    let a = (-1.0 / (rate * tau)).exp();
    let mut y = 0.0;
    sp.iter()
        .map(|&s| {
            let out = y;
            y = s + (y - s) * a;
            out
        })
        .collect()
}

/// The response of y'' = ω²(sp − y) − 2ζω y' to a setpoint held between samples
/// (RK4 with 20 steps per sample).
fn second_order(sp: &[f64], rate: f64, omega: f64, zeta: f64) -> Vec<f64> {
    let (mut y, mut v) = (0.0f64, 0.0f64);
    let h = 1.0 / (rate * 20.0);
    let accel = |y: f64, v: f64, s: f64| omega * omega * (s - y) - 2.0 * zeta * omega * v;
    sp.iter()
        .map(|&s| {
            let out = y;
            for _ in 0..20 {
                let (k1y, k1v) = (v, accel(y, v, s));
                let (k2y, k2v) = (
                    v + 0.5 * h * k1v,
                    accel(y + 0.5 * h * k1y, v + 0.5 * h * k1v, s),
                );
                let (k3y, k3v) = (
                    v + 0.5 * h * k2v,
                    accel(y + 0.5 * h * k2y, v + 0.5 * h * k2v, s),
                );
                let (k4y, k4v) = (v + h * k3v, accel(y + h * k3y, v + h * k3v, s));
                y += h / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y);
                v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            }
            out
        })
        .collect()
}

/// 2 s windows: the Hann window on both signals biases the estimate (a response
/// quicker and lower than the loop's by several % with 1 s windows), less the longer
/// the window is against the loop's time constant.
fn long_windows() -> StepResponseOptions {
    StepResponseOptions::default().window_s(2.0)
}

#[test]
fn first_order_loop_rises_in_tau_ln_9_without_overshoot() {
    let (rate, tau) = (250.0, 0.05);
    let sp = random_steps(240 * 250, rate, 5);
    let mut rng = Rng::new(6);
    let y: Vec<f64> = first_order(&sp, rate, tau)
        .into_iter()
        .map(|v| v + 0.01 * gaussian(&mut rng))
        .collect();
    let step = step_response(&sp, &y, rate, &long_windows()).unwrap();
    assert!(step.windows.len() > 50, "{}", step.windows.len());
    let m = step.metrics().unwrap();
    let expected = tau * 9f64.ln();
    let rise = m.rise_time_s.unwrap();
    assert!(
        (rise - expected).abs() / expected < 0.08,
        "rise {rise} vs {expected}"
    );
    assert!(
        m.overshoot_percent < 2.0,
        "overshoot {}",
        m.overshoot_percent
    );
    assert!(
        (m.final_value - 1.0).abs() < 0.05,
        "final {}",
        m.final_value
    );
    let settle = tau * 20f64.ln();
    let settling = m.settling_time_s.unwrap();
    assert!(
        (settling - settle).abs() / settle < 0.1,
        "settling {settling} vs {settle}"
    );
}

#[test]
fn second_order_loop_overshoots_as_its_damping_says() {
    let rate = 250.0;
    for zeta in [0.3, 0.5, 0.7] {
        let omega = 2.0 * PI * 6.0;
        let sp = random_steps(240 * 250, rate, 5);
        let y = second_order(&sp, rate, omega, zeta);
        let step = step_response(&sp, &y, rate, &long_windows()).unwrap();
        let m = step.metrics().unwrap();
        let expected = 100.0 * (-PI * zeta / (1.0 - zeta * zeta).sqrt()).exp();
        assert!(
            (m.overshoot_percent - expected).abs() < 3.0,
            "ζ = {zeta}: overshoot {} vs {expected}",
            m.overshoot_percent
        );
        // The peak of the textbook response comes at π / (ω√(1−ζ²)).
        let peak_time = PI / (omega * (1.0 - zeta * zeta).sqrt());
        assert!(
            (m.peak_time_s - peak_time).abs() < 0.01,
            "peak at {}",
            m.peak_time_s
        );
    }
}

#[test]
fn still_setpoints_are_no_excitation() {
    let sp = vec![0.2; 1000];
    let y = vec![0.2; 1000];
    assert_eq!(
        step_response(&sp, &y, 250.0, &StepResponseOptions::default()),
        Err(AnalysisError::NoExcitation { windows: 7 })
    );
    let sp = random_steps(1000, 250.0, 1);
    assert!(matches!(
        step_response(
            &sp,
            &sp,
            250.0,
            &StepResponseOptions::default().min_excitation(5.0)
        ),
        Err(AnalysisError::NoExcitation { .. })
    ));
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let empty: [f64; 0] = [];
    let one = [1.0f64];
    let mut nan = vec![0.0f64; 100];
    nan[40] = f64::NAN;
    let ok = vec![0.0f64; 100];
    let too_few = AnalysisError::TooFewSamples { needed: 16, got: 0 };
    assert_eq!(
        psd(&empty, 100.0, &PsdOptions::default()),
        Err(too_few.clone())
    );
    assert_eq!(amplitude_spectrum(&empty, 100.0), Err(too_few.clone()));
    assert_eq!(
        spectrogram(&empty, 100.0, &SpectrogramOptions::default()),
        Err(too_few)
    );
    assert!(matches!(
        psd(&one, 100.0, &PsdOptions::default()),
        Err(AnalysisError::TooFewSamples { got: 1, .. })
    ));
    assert_eq!(
        psd(&nan, 100.0, &PsdOptions::default()),
        Err(AnalysisError::NotFinite { index: 40 })
    );
    assert_eq!(
        amplitude_spectrum(&nan, 100.0),
        Err(AnalysisError::NotFinite { index: 40 })
    );
    assert_eq!(
        spectrogram(&nan, 100.0, &SpectrogramOptions::default()),
        Err(AnalysisError::NotFinite { index: 40 })
    );
    for rate in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(psd(&ok, rate, &PsdOptions::default()).is_err());
        assert!(amplitude_spectrum(&ok, rate).is_err());
        assert!(spectrogram(&ok, rate, &SpectrogramOptions::default()).is_err());
        assert!(step_response(&ok, &ok, rate, &StepResponseOptions::default()).is_err());
    }
    assert!(psd(&ok, 100.0, &PsdOptions::default().segment_len(101)).is_err());
    assert!(spectrogram(&ok, 100.0, &SpectrogramOptions::default().overlap(1.0)).is_err());
    let d = StepResponseOptions::default();
    assert_eq!(
        step_response(&ok, &ok[..99], 100.0, &d),
        Err(AnalysisError::LengthMismatch {
            first: 100,
            second: 99
        })
    );
    assert_eq!(
        step_response(&one, &one, 100.0, &d),
        Err(AnalysisError::TooFewSamples {
            needed: 100,
            got: 1
        })
    );
    assert_eq!(
        step_response(&nan, &ok, 100.0, &d),
        Err(AnalysisError::NotFinite { index: 40 })
    );
    for bad in [
        d.clone().overlap(1.0),
        d.clone().regularisation(0.0),
        d.clone().min_excitation(f64::NAN),
        d.clone().cutoff_hz(Some(-1.0)),
        d.clone().window_s(0.01),
        d.clone().response_s(2.0),
    ] {
        assert!(matches!(
            step_response(&ok, &ok, 100.0, &bad),
            Err(AnalysisError::InvalidParameter { .. })
        ));
    }
    assert_eq!(step_metrics(&[], &[]), None);
    assert_eq!(step_metrics(&[0.0; 10], &[0.0; 10]), None);
    assert_eq!(step_metrics(&[0.0; 10], &[f64::NAN; 10]), None);
}
