//! [`Aligned`]: a struct of bound topics, declared once, checked against a log once
//! (every field that does not fit reported together), and read at each step.

use crate::typed::error::TypedError;
use crate::typed::message::ULogMessage;

use super::{Alignment, Method, Samples};

/// A struct whose fields are bound topics, `Option<Binding>` each, derived with
/// `#[derive(Aligned)]` (feature `derive`) and read at the steps of an [`Alignment`]
/// with [`Alignment::read`]: one struct per step, each field the value of its topic at
/// the step by its method, `None` where the topic has none.
///
/// Field attributes: `#[ulog(instance = N)]` (the topic instance, default 0) and
/// `#[ulog(method = "previous" | "nearest" | "linear")]` (default `previous`; the
/// [module](super) has the rules).
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::align::{AlignOptions, Aligned, Grid};
/// use ulog_core::ULogMessage;
///
/// #[derive(ULogMessage)]
/// # #[ulog(crate = "ulog_core")]
/// struct VehicleAttitude { timestamp: u64, q: [f32; 4] }
/// #[derive(ULogMessage)]
/// # #[ulog(crate = "ulog_core")]
/// struct BatteryStatus { timestamp: u64, voltage_v: f32 }
///
/// #[derive(Aligned)]
/// # #[ulog(crate = "ulog_core")]
/// struct Now {
///     attitude: Option<VehicleAttitude>,
///     #[ulog(instance = 1, method = "linear")]
///     battery: Option<BatteryStatus>,
/// }
///
/// let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes).unwrap();
/// let steps = log.align(&Grid::topic("vehicle_attitude", 0), &AlignOptions::default()).unwrap();
/// let mut now = steps.read::<Now>().unwrap(); // both checked here
/// now.seek(log.span().at(5.0)); // O(log n)
/// let (t, first) = now.next().unwrap();
/// assert_eq!(first.attitude.unwrap().timestamp, t);
/// for (_, step) in now {
///     if let Some(b) = step.battery {
///         assert!(b.voltage_v > 10.0);
///     }
/// }
/// # }
/// ```
pub trait Aligned: Sized {
    /// The fields, in declaration order: their topics, instances and methods.
    const FIELDS: &'static [AlignedField];

    /// Opens every field's topic at the steps (generated; call
    /// [`Alignment::read`]). Every field whose binding does not fit the log is an
    /// entry of the error.
    #[doc(hidden)]
    fn open<'s>(steps: &'s Alignment<'_, '_>) -> Result<__Next<'s, Self>, AlignedError>;

    /// Checks every field's binding against its topic's layout, for a one-pass
    /// alignment (generated; call [`AlignedStream::new`](super::AlignedStream::new)).
    #[doc(hidden)]
    fn __decoder(layouts: &__Layouts) -> Result<__Decode<Self>, AlignedError>;
}

/// Each field's topic layout, or why there is none (generated code's use).
#[doc(hidden)]
pub type __Layouts = [Result<std::sync::Arc<ulog_format::Layout>, TypedError>];

/// Decodes a struct from the rows of a one-pass step (generated code's use).
#[doc(hidden)]
pub type __Decode<S> = Box<dyn Fn(&[Option<super::Row<'_>>]) -> S>;

/// The plans of a struct's fields for their layouts, every misfit collected
/// (generated code's use).
#[doc(hidden)]
pub struct __Plans<'l> {
    layouts: &'l __Layouts,
    fields: &'static [AlignedField],
    errors: Vec<(AlignedField, TypedError)>,
}

impl<'l> __Plans<'l> {
    #[doc(hidden)]
    pub fn new(layouts: &'l __Layouts, fields: &'static [AlignedField]) -> Self {
        __Plans {
            layouts,
            fields,
            errors: Vec::new(),
        }
    }

    /// Field `i`'s plan, or its error noted.
    #[doc(hidden)]
    pub fn plan<T: ULogMessage>(&mut self, i: usize) -> Option<crate::typed::Plan<T>> {
        let field = self.fields[i];
        let layout = match &self.layouts[i] {
            Ok(l) => l,
            Err(e) => {
                self.errors.push((field, e.clone()));
                return None;
            }
        };
        match crate::typed::Plan::<T>::new(layout) {
            Ok(p) => Some(p),
            Err(m) => {
                let kind = crate::typed::TypedErrorKind::Mismatch(Box::new(m));
                self.errors.push((field, TypedError::new(kind, None, None)));
                None
            }
        }
    }

    #[doc(hidden)]
    pub fn error(self) -> AlignedError {
        AlignedError {
            fields: self.errors,
        }
    }
}

/// Field `i`'s value in a one-pass step's rows (generated code's use).
#[doc(hidden)]
pub fn __decode<T: ULogMessage>(
    plan: &crate::typed::Plan<T>,
    rows: &[Option<super::Row<'_>>],
    i: usize,
) -> Option<T> {
    let row = rows.get(i)?.as_ref()?;
    plan.decode(row.bytes()).ok()
}

/// One field of an [`Aligned`] struct.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlignedField {
    /// The field's name in the struct.
    pub field: &'static str,
    /// The topic of its binding (its name; aliases are tried too).
    pub topic: &'static str,
    /// The topic instance.
    pub multi_id: u8,
    /// How its value at a step is found.
    pub method: Method,
}

/// Why an [`Aligned`] struct cannot be read from a log: each field whose binding does
/// not fit (its topic or instance missing, its format different), all of them.
#[derive(Debug, Clone)]
pub struct AlignedError {
    fields: Vec<(AlignedField, TypedError)>,
}

impl AlignedError {
    /// Each field that does not fit, with why.
    pub fn fields(&self) -> &[(AlignedField, TypedError)] {
        &self.fields
    }
}

impl core::fmt::Display for AlignedError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let n = self.fields.len();
        write!(
            f,
            "{n} field{} of the aligned struct do{} not fit this log:",
            if n == 1 { "" } else { "s" },
            if n == 1 { "es" } else { "" }
        )?;
        for (field, e) in &self.fields {
            write!(
                f,
                "\n  `{}` ({} instance {}): {e}",
                field.field, field.topic, field.multi_id
            )?;
        }
        Ok(())
    }
}

impl std::error::Error for AlignedError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.fields
            .first()
            .map(|(_, e)| e as &(dyn std::error::Error + 'static))
    }
}

/// What generated code steps a struct with: `None` moves to the next step and returns
/// its struct; `Some(step)` repositions every field at `step` (and returns `None`).
#[doc(hidden)]
pub type __Next<'s, S> = Box<dyn FnMut(Option<usize>) -> Option<S> + 's>;

/// Opens the fields of a struct one by one, collecting what does not fit.
#[doc(hidden)]
pub struct __Check<'s, 'l, 'a> {
    steps: &'s Alignment<'l, 'a>,
    fields: &'static [AlignedField],
    errors: Vec<(AlignedField, TypedError)>,
}

impl<'s, 'l, 'a> __Check<'s, 'l, 'a> {
    #[doc(hidden)]
    pub fn new(steps: &'s Alignment<'l, 'a>, fields: &'static [AlignedField]) -> Self {
        __Check {
            steps,
            fields,
            errors: Vec::new(),
        }
    }

    /// Field `i`'s topic at the steps, or `None` with why recorded.
    #[doc(hidden)]
    pub fn topic<T: ULogMessage>(&mut self, i: usize) -> Option<Samples<'s, 'a, T>> {
        let field = self.fields[i];
        match self.steps.topic::<T>(field.multi_id, field.method) {
            Ok(s) => Some(s),
            Err(e) => {
                self.errors.push((field, e));
                None
            }
        }
    }

    /// Every field that did not fit.
    #[doc(hidden)]
    pub fn error(self) -> AlignedError {
        AlignedError {
            fields: self.errors,
        }
    }
}

/// The structs of an [`Aligned`] type at the steps of an alignment, with each step's
/// time ([`Alignment::read`]).
pub struct AlignedSteps<'s, S> {
    times: &'s [u64],
    step: usize,
    next: __Next<'s, S>,
}

impl<S> AlignedSteps<'_, S> {
    /// Repositions at the first step at or after `t_us` (boot microseconds): a binary
    /// search over the steps and over each topic's rows, O(log n).
    pub fn seek(&mut self, t_us: u64) {
        self.step = self.times.partition_point(|&t| t < t_us);
        (self.next)(Some(self.step));
    }

    /// The steps left.
    pub fn remaining(&self) -> usize {
        self.times.len() - self.step
    }
}

impl<S> Iterator for AlignedSteps<'_, S> {
    type Item = (u64, S);
    fn next(&mut self) -> Option<(u64, S)> {
        let t = *self.times.get(self.step)?;
        self.step += 1;
        (self.next)(None).map(|s| (t, s))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.remaining(), Some(self.remaining()))
    }
}

impl<S> core::fmt::Debug for AlignedSteps<'_, S> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("AlignedSteps")
            .field("steps", &self.times.len())
            .field("step", &self.step)
            .finish_non_exhaustive()
    }
}

impl<'l, 'a> Alignment<'l, 'a> {
    /// The structs of [`Aligned`] type `S` at each step, with the step's time: every
    /// field's binding is checked against the log here, once, and every one that does
    /// not fit is named in the error.
    pub fn read<S: Aligned>(&self) -> Result<AlignedSteps<'_, S>, AlignedError> {
        Ok(AlignedSteps {
            times: &self.times,
            step: 0,
            next: S::open(self)?,
        })
    }
}

/// A player replays the structs of an alignment step by step
/// ([`Player`](crate::replay::Player)), seeking by time.
impl<S> crate::replay::Timeline for AlignedSteps<'_, S> {
    type Item = S;
    fn advance(&mut self) -> Option<(u64, S)> {
        self.next()
    }
    fn seek(&mut self, t_us: u64) {
        AlignedSteps::seek(self, t_us)
    }
}
