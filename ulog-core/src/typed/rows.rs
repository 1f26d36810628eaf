//! [`TypedRows`]: the rows of one topic instance of a parsed log, decoded into a
//! binding; [`ULog::read`] and [`ULog::read_instances`].

use core::marker::PhantomData;

use crate::access::lookup::TopicNotFound;
use crate::access::topic::{Payloads, Topic};
use crate::log::ulog::ULog;

use super::error::{DecodeError, TypedError};
use super::message::ULogMessage;
use super::plan::{BindingOf, Plan, RawPlan};
use super::schema::FieldKind;
use crate::audited::WireImage;

/// The rows of one topic instance decoded into `T` (see [`ULog::read`]).
pub struct TypedRows<'l, 'a, T> {
    topic: Topic<'l, 'a>,
    plan: Plan<T>,
}

impl<'l, 'a, T: ULogMessage> TypedRows<'l, 'a, T> {
    /// The topic instance.
    pub fn topic(&self) -> Topic<'l, 'a> {
        self.topic
    }

    /// The plan made for it (exact or mapped, which optional fields the log has).
    pub fn plan(&self) -> &Plan<T> {
        &self.plan
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.topic.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.topic.is_empty()
    }

    /// Row `i`, decoded.
    pub fn get(&self, i: usize) -> Option<Result<T, TypedError>> {
        let payload = self.topic.payload(i)?;
        Some(self.plan.decode(payload).map_err(|e| {
            // Row `i` has a payload, so it has an offset: looked up only for an error.
            let offset = self.topic.message_offsets().get(i).unwrap_or(0);
            TypedError::decode(self.topic.subscription(), offset, e)
        }))
    }

    /// Every row, decoded, in file order. Framing has checked each payload's size
    /// against the format, so decoding does not fail on a log this reader parsed.
    pub fn iter(&self) -> RowsIter<'_, 'a, T> {
        let image = match T::READS_IMAGE {
            true => Some((T::KIND, core::mem::size_of::<T::Wire>())),
            false => None,
        };
        RowsIter {
            cursor: Cursor::new(self.topic, self.plan.raw(), image),
            plan: &self.plan,
        }
    }

    /// Every row borrowed in place as `&T`, without a copy; refused once, with the
    /// reason, when the rows cannot be borrowed as `T`
    /// ([`TypedErrorKind::NoView`](super::TypedErrorKind::NoView)).
    ///
    /// `T` must be a binding whose memory is its wire image: derive it with
    /// `#[ulog(view)]` and `#[repr(C)]` (Rust would reorder the fields otherwise), with
    /// fields of `u8`, `i8`, [`CharArray<N>`](super::CharArray), the [`le`](super::le)
    /// little-endian types (`le::U64`, `le::F32`, …), arrays of these, and nested such
    /// bindings (the derive checks it at compile time).
    ///
    /// And `T` must be the log's layout ([`PlanKind::Exact`](super::PlanKind::Exact)):
    /// the log's fields in the log's order from the first one, the padding between
    /// them included, each of the log's type and length; the fields after the last
    /// one `T` needs may be left out, and the trailing padding should be (PX4 never
    /// writes it: rows without it are refused for a `T` that declares it). A hand-written view therefore borrows the logs of the firmware
    /// whose format it copies (and of any firmware that only adds fields after its
    /// last one); on another layout (a field added before, moved or retyped, as
    /// between PX4 releases) it is refused and [`iter`](TypedRows::iter) decodes the
    /// rows by copy. `ulog codegen --views` and `ulog_module!(views; …)` write views
    /// from a log's own formats. Each row is an `Ok` on a log this reader parsed.
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// use ulog_core::typed::{le, TypedErrorKind};
    ///
    /// // `vehicle_attitude` as PX4 logs it from v1.13 on: the log's fields in the
    /// // log's order, up to `q`, which is all this view needs.
    /// #[derive(ulog_core::ULogMessage)]
    /// #[ulog(crate = "ulog_core", view)]
    /// #[repr(C)]
    /// struct VehicleAttitude { timestamp: le::U64, timestamp_sample: le::U64, q: [le::F32; 4] }
    ///
    /// // A log as PX4 v1.13 and later write it (without the trailing padding).
    /// let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    /// b.format("vehicle_attitude:uint64_t timestamp;uint64_t timestamp_sample;float[4] q;\
    ///           float[4] delta_q_reset;uint8_t quat_reset_counter;uint8_t[7] _padding0;");
    /// b.subscribe(0, 0, "vehicle_attitude");
    /// let mut payload = [1000u64.to_le_bytes(), 990u64.to_le_bytes()].concat();
    /// for x in [1.0f32, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0] {
    ///     payload.extend(x.to_le_bytes());
    /// }
    /// payload.push(0); // quat_reset_counter
    /// b.data(0, &payload);
    /// let log = ulog_core::ULog::parse(b.bytes()).unwrap();
    /// let rows = log.read::<VehicleAttitude>(0).unwrap();
    /// let first: &VehicleAttitude = rows.views().unwrap().next().unwrap().unwrap();
    /// assert_eq!(first.q[0].get(), 1.0);
    ///
    /// // Without `timestamp_sample` the binding is not that layout (its `q` is at byte
    /// // 8, the log's at 16): refused once, with the reason; `iter()` still decodes it.
    /// #[derive(ulog_core::ULogMessage)]
    /// #[ulog(crate = "ulog_core", name = "vehicle_attitude", view)]
    /// #[repr(C)]
    /// struct Quaternion { timestamp: le::U64, q: [le::F32; 4] }
    ///
    /// let rows = log.read::<Quaternion>(0).unwrap();
    /// let Err(e) = rows.views() else { panic!("borrowed") };
    /// assert!(matches!(e.kind(), TypedErrorKind::NoView { .. }));
    /// assert_eq!(rows.iter().next().unwrap().unwrap().q[0].get(), 1.0);
    /// # }
    /// ```
    pub fn views(
        &self,
    ) -> Result<impl ExactSizeIterator<Item = Result<&'a T, TypedError>> + '_, TypedError>
    where
        T: WireImage + 'a,
    {
        self.can_borrow()?;
        let offsets = self.topic.message_offsets();
        let topic = self.topic.subscription();
        Ok(self.topic.payloads().zip(offsets).map(move |(p, o)| {
            self.plan
                .view(p)
                .map_err(|e| TypedError::decode(topic, o, e))
        }))
    }

    /// Whether every row can be borrowed as `T`: an exact plan, and no row shorter
    /// than `T` (a binding that declares trailing padding the log's writer left out).
    fn can_borrow(&self) -> Result<(), TypedError> {
        let sub = self.topic.subscription();
        let refuse = |why: String| Err(TypedError::no_view(sub, T::schema(), why));
        if let Some(why) = self.plan.why_mapped() {
            return refuse(format!(
                "{why}, so the binding is not the log's layout (a view has the log's fields in its order from the first one, with the padding between them)"
            ));
        }
        let own = core::mem::size_of::<T>();
        let min_size = sub.layout().map_or(0, |l| l.min_size());
        if own > min_size {
            let short = self.topic.payloads().filter(|p| p.len() < own).count();
            if short > 0 {
                return refuse(format!(
                    "{short} of {} rows have fewer bytes than the binding's {own}: leave the trailing padding (that the log's writer left out) out of the binding",
                    self.len()
                ));
            }
        }
        Ok(())
    }
}

impl<'l, 'a> Topic<'l, 'a> {
    /// The topic's rows decoded into `T`, its format checked against `T` once: an
    /// error lists every difference.
    pub fn read<T: ULogMessage>(&self) -> Result<TypedRows<'l, 'a, T>, TypedError> {
        let raw = self.plan(&BindingOf::of::<T>())?;
        Ok(TypedRows {
            topic: *self,
            plan: Plan::from_raw(raw),
        })
    }

    /// The plan of this topic for a binding: what [`read`](Topic::read) does past
    /// what depends on the binding's type.
    fn plan(&self, binding: &BindingOf) -> Result<RawPlan, TypedError> {
        let sub = self.subscription();
        match sub.layout() {
            Ok(layout) => RawPlan::build(binding, layout).map_err(|m| TypedError::mismatch(sub, m)),
            Err(e) => Err(TypedError::no_layout(sub, e)),
        }
    }
}

impl<'a> ULog<'a> {
    /// Instance `multi_id` of the topic `T` binds, decoded into `T`.
    ///
    /// The topic is `T`'s ULog name: `#[ulog(name = "…")]`, or the struct's name in
    /// snake case (`VehicleLocalPosition` → `vehicle_local_position`). A name the log
    /// does not have is an error listing the closest topic names (and saying when the
    /// name came from the struct's name); a format that does not fit `T` lists every
    /// difference.
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// #[derive(ulog_core::ULogMessage)]
    /// #[ulog(crate = "ulog_core")]
    /// struct BatteryStatus { timestamp: u64, voltage_v: f32, remaining: f32 }
    ///
    /// let bytes = ulog_core::testing::sample_log();
    /// let log = ulog_core::ULog::parse(&bytes).unwrap();
    /// let rows = log.read::<BatteryStatus>(1).unwrap();
    /// let first = rows.iter().next().unwrap().unwrap();
    /// assert_eq!(first.voltage_v, 16.7);
    /// # }
    /// ```
    pub fn read<T: ULogMessage>(&self, multi_id: u8) -> Result<TypedRows<'_, 'a, T>, TypedError> {
        let found = self.find_topic(T::NAME, T::ALIASES, multi_id);
        match found {
            Ok(topic) => topic.read(),
            Err(missing) => Err(TypedError::not_found(missing, T::schema())),
        }
    }

    /// Every instance of the topic `T` binds, by multi_id, each decoded into `T` or
    /// the error of that instance alone (the others are read whatever one of them
    /// holds). The outer error: the log has no instance of the topic at all.
    ///
    /// The instances come as an iterator ([`Instances`]); `.collect::<Vec<_>>()`
    /// makes the vector this returned before (a type per binding that a program
    /// compiled for each binding it read).
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// #[derive(ulog_core::ULogMessage)]
    /// #[ulog(crate = "ulog_core")]
    /// struct BatteryStatus { timestamp: u64, voltage_v: f32 }
    ///
    /// let bytes = ulog_core::testing::sample_log();
    /// let log = ulog_core::ULog::parse(&bytes).unwrap();
    /// let instances = log.read_instances::<BatteryStatus>().unwrap();
    /// let named = log.topics().filter(|t| t.name() == "battery_status").count();
    /// assert_eq!(instances.len(), named);
    /// for rows in instances {
    ///     // Each instance planned on its own: one that does not fit is its own error.
    ///     let rows = rows.unwrap();
    ///     let first = rows.iter().next().unwrap().unwrap();
    ///     assert!(first.voltage_v > 0.0, "instance {}", rows.topic().multi_id());
    /// }
    /// # }
    /// ```
    pub fn read_instances<T: ULogMessage>(&self) -> Result<Instances<'_, 'a, T>, TypedError> {
        match self.plan_instances(&BindingOf::of::<T>(), T::NAME, T::ALIASES) {
            Ok(planned) => Ok(Instances {
                planned,
                binding: PhantomData,
            }),
            Err(e) => Err(e),
        }
    }

    /// [`read_instances`](ULog::read_instances) past what depends on the binding's
    /// type: each instance's plan, or its error.
    fn plan_instances(
        &self,
        binding: &BindingOf,
        name: &'static str,
        aliases: &'static [&'static str],
    ) -> Result<std::vec::IntoIter<Planned<'_, 'a>>, TypedError> {
        let instances = match self.instances_of(name, aliases) {
            Ok(found) => found,
            Err(missing) => return Err(TypedError::not_found(missing, binding.schema())),
        };
        let planned: Vec<_> = instances
            .into_iter()
            .map(|topic| topic.plan(binding).map(|raw| (topic, raw)))
            .collect();
        Ok(planned.into_iter())
    }

    /// Instance `multi_id` of the first of `name` and `aliases` the log has it under,
    /// or what the log has instead.
    fn find_topic(
        &self,
        name: &'static str,
        aliases: &'static [&'static str],
        multi_id: u8,
    ) -> Result<Topic<'_, 'a>, TopicNotFound> {
        let names = core::iter::once(name).chain(aliases.iter().copied());
        for name in names {
            if let Some(t) = self
                .topics()
                .find(|t| t.name() == name && t.multi_id() == multi_id)
            {
                return Ok(t);
            }
        }
        Err(self.missing(name, aliases, Some(multi_id)))
    }

    /// Every instance of the first of `name` and `aliases` the log has, or what the
    /// log has instead.
    fn instances_of(
        &self,
        name: &'static str,
        aliases: &'static [&'static str],
    ) -> Result<Vec<Topic<'_, 'a>>, TopicNotFound> {
        let names = core::iter::once(name).chain(aliases.iter().copied());
        for name in names {
            let found = self.topic_instances(name);
            if !found.is_empty() {
                return Ok(found);
            }
        }
        Err(self.missing(name, aliases, None))
    }

    /// What the log has instead of the topic `name` (also known as `aliases`): the
    /// instances of the first of its names the log has, else the closest names to its
    /// own, its aliases said.
    fn missing(
        &self,
        name: &'static str,
        aliases: &'static [&'static str],
        multi_id: Option<u8>,
    ) -> TopicNotFound {
        let has = |name: &&str| !self.topic_instances(name).is_empty();
        let mut names = core::iter::once(name).chain(aliases.iter().copied());
        match names.find(has) {
            Some(name) => TopicNotFound::in_log(self, name, multi_id),
            None => {
                let mut missing = TopicNotFound::in_log(self, name, multi_id);
                missing.aliases = aliases.iter().map(|a| (*a).to_owned()).collect();
                missing
            }
        }
    }
}

/// The rows of a [`TypedRows`], decoded in file order ([`TypedRows::iter`]).
pub struct RowsIter<'r, 'a, T> {
    cursor: Cursor<'r, 'a>,
    plan: &'r Plan<T>,
}

/// What [`RowsIter`] walks, the same for every binding: each row's payload, and for
/// a binding read through its wire image that image. Kept apart from the binding so
/// that its code is compiled once, not once per binding a program reads
/// (bench/README.md, what `ulog_module!` costs a crate).
struct Cursor<'r, 'a> {
    payloads: Payloads<'r, 'a>,
    topic: Topic<'r, 'a>,
    plan: &'r RawPlan,
    /// A binding read through its wire image: its kind, and its image when the
    /// payload's prefix is not (filled from the payload).
    image: Option<(FieldKind, Vec<u8>)>,
}

impl<'r, 'a> Cursor<'r, 'a> {
    fn new(topic: Topic<'r, 'a>, plan: &'r RawPlan, image: Option<(FieldKind, usize)>) -> Self {
        Cursor {
            payloads: topic.payloads(),
            topic,
            plan,
            image: image.map(|(kind, size)| (kind, vec![0; size])),
        }
    }

    /// The row last handed out and where its message starts, for an error: the
    /// offsets are not followed row by row beside the payloads (bench/README.md, what
    /// `ulog_module!` costs a crate: the cost at run time).
    #[cold]
    fn last(&self) -> (&'a [u8], u64) {
        let row = (self.topic.len() - self.payloads.len()).saturating_sub(1);
        let offset = self.topic.message_offsets().get(row).unwrap_or(0);
        (self.topic.payload(row).unwrap_or(&[]), offset)
    }

    /// The next row's wire image (a binding read through its image): `None` at the
    /// end, `Some(None)` for a row refused ([`refused`](Cursor::refused) says why).
    /// A slice or nothing, not a `Result` that holds the error, so that the call a
    /// row costs returns little.
    fn next_image(&mut self) -> Option<Option<&[u8]>> {
        let payload = self.payloads.next()?;
        Some(match self.image.as_mut() {
            Some((kind, wire)) => self.plan.image(payload, wire, *kind).ok(),
            // `iter` gives every binding read through its image one: were it missing,
            // the row would be refused with its length, not left out.
            None => None,
        })
    }

    /// Why the last row was refused: its image, or a binding that did not take it.
    #[cold]
    #[inline(never)]
    fn refused(&mut self) -> TypedError {
        let (payload, offset) = self.last();
        let error = match self.image.as_mut() {
            Some((kind, wire)) => self.plan.image(payload, wire, *kind).err(),
            None => None,
        };
        let error = error.unwrap_or_else(|| self.plan.length_error(payload.len()));
        TypedError::decode(self.topic.subscription(), offset, error)
    }

    /// The error of the last row, refused by the plan.
    #[cold]
    #[inline(never)]
    fn failed(&self, error: DecodeError) -> TypedError {
        TypedError::decode(self.topic.subscription(), self.last().1, error)
    }
}

impl<T: ULogMessage> RowsIter<'_, '_, T> {
    /// The next row of a binding read through its wire image.
    #[inline]
    fn next_from_image(&mut self) -> Option<Result<T, TypedError>> {
        let plan = self.cursor.plan;
        let value = match self.cursor.next_image()? {
            Some(image) => T::from_image(image, plan.present()),
            None => None,
        };
        Some(match value {
            Some(value) => Ok(value),
            None => Err(self.cursor.refused()),
        })
    }

    /// The next row of any other binding.
    #[inline]
    fn next_decoded(&mut self) -> Option<Result<T, TypedError>> {
        let payload = self.cursor.payloads.next()?;
        Some(match self.plan.decode(payload) {
            Ok(value) => Ok(value),
            Err(e) => Err(self.cursor.failed(e)),
        })
    }
}

impl<T: ULogMessage> Iterator for RowsIter<'_, '_, T> {
    type Item = Result<T, TypedError>;

    #[inline]
    fn next(&mut self) -> Option<Result<T, TypedError>> {
        if T::READS_IMAGE {
            self.next_from_image()
        } else {
            self.next_decoded()
        }
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.cursor.payloads.size_hint()
    }
}

impl<T: ULogMessage> ExactSizeIterator for RowsIter<'_, '_, T> {}

impl<T: ULogMessage> core::iter::FusedIterator for RowsIter<'_, '_, T> {}

impl<T> core::fmt::Debug for RowsIter<'_, '_, T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("RowsIter")
            .field("topic", &self.cursor.topic)
            .field("binding", &core::any::type_name::<T>())
            .field("left", &self.cursor.payloads.len())
            .finish()
    }
}

/// An instance's topic and plan, or its error.
type Planned<'l, 'a> = Result<(Topic<'l, 'a>, RawPlan), TypedError>;

/// Every instance of a topic, each planned for `T` or the error of that instance
/// alone, in multi_id order ([`ULog::read_instances`]): iterate it for each
/// instance's [`TypedRows`].
///
/// The instances are held apart from `T`, so that the code of the collection is
/// compiled once and not once per binding a program reads.
pub struct Instances<'l, 'a, T> {
    planned: std::vec::IntoIter<Planned<'l, 'a>>,
    binding: PhantomData<fn() -> T>,
}

impl<'l, 'a, T: ULogMessage> Instances<'l, 'a, T> {
    /// An instance's rows for `T`, or its error.
    #[inline]
    fn rows(planned: Planned<'l, 'a>) -> Result<TypedRows<'l, 'a, T>, TypedError> {
        match planned {
            Ok((topic, raw)) => Ok(TypedRows {
                topic,
                plan: Plan::from_raw(raw),
            }),
            Err(e) => Err(e),
        }
    }
}

impl<'l, 'a, T: ULogMessage> Iterator for Instances<'l, 'a, T> {
    type Item = Result<TypedRows<'l, 'a, T>, TypedError>;

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        Some(Self::rows(self.planned.next()?))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.planned.size_hint()
    }
}

impl<T: ULogMessage> DoubleEndedIterator for Instances<'_, '_, T> {
    fn next_back(&mut self) -> Option<Self::Item> {
        Some(Self::rows(self.planned.next_back()?))
    }
}

impl<T: ULogMessage> ExactSizeIterator for Instances<'_, '_, T> {}

impl<T: ULogMessage> core::iter::FusedIterator for Instances<'_, '_, T> {}

impl<T> core::fmt::Debug for Instances<'_, '_, T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Instances")
            .field("binding", &core::any::type_name::<T>())
            .field("left", &self.planned.len())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::LogBuilder;
    use crate::typed::binding::{Binding, Reader, SchemaCell, Writer};
    use crate::typed::hand_binding::Pair as Plain;
    use crate::typed::Schema;

    /// A binding of a known format, read through its wire image, as `ulog_module!`
    /// writes them.
    #[derive(Copy)]
    struct Pair {
        a: u32,
        b: u16,
    }

    crate::__binding_impls!(Pair);

    impl Binding for Pair {
        type Wire = [u8; 6];
        const FORMAT: &'static str = "pair:uint32_t a;uint16_t b;";
        const SOURCES: usize = 2;
        fn schema() -> &'static Schema {
            static SCHEMA: SchemaCell = SchemaCell::new();
            SCHEMA.get::<Self>()
        }
        fn read(r: &mut Reader<'_>) -> Self {
            Pair {
                a: r.get(),
                b: r.get(),
            }
        }
        fn write(&self, w: &mut Writer<'_>) {
            w.put(&self.a);
            w.put(&self.b);
        }
    }

    /// A log of `format` with two instances of the topic `pair`, each with `rows`
    /// payloads of `before` bytes of 7, `a` (u32: the row, plus 100 on instance 1),
    /// `b` (u16: the row), then `after` zero bytes.
    fn log(format: &str, rows: u32, before: usize, after: usize) -> Vec<u8> {
        let mut b = LogBuilder::new(1, 0);
        b.format(format);
        b.subscribe(0, 0, "pair");
        b.subscribe(1, 1, "pair");
        for i in 0..rows {
            for m in 0..2u16 {
                let mut payload = vec![7u8; before];
                payload.extend((i + 100 * u32::from(m)).to_le_bytes());
                payload.extend((i as u16).to_le_bytes());
                payload.extend(vec![0; after]);
                b.data(m, &payload);
            }
        }
        b.bytes().to_vec()
    }

    #[test]
    fn every_instance_and_row_read_through_the_image_in_either_direction() {
        // Exact (the binding's layout) and mapped (a field the binding leaves out
        // before its own): both go through the cursor's image.
        for (format, before) in [
            ("pair:uint32_t a;uint16_t b;", 0),
            ("pair:uint8_t[3] z;uint32_t a;uint16_t b;", 3),
        ] {
            let bytes = log(format, 5, before, 0);
            let log = ULog::parse(&bytes).unwrap();
            let instances = log.read_instances::<Pair>().unwrap();
            assert_eq!(instances.len(), 2, "{format}");
            let backwards: Vec<u8> = log
                .read_instances::<Pair>()
                .unwrap()
                .rev()
                .map(|r| r.unwrap().topic().multi_id())
                .collect();
            assert_eq!(backwards, [1, 0]);
            for (m, rows) in instances.enumerate() {
                let rows = rows.unwrap();
                let iter = rows.iter();
                assert_eq!(iter.len(), 5);
                let got: Vec<Pair> = iter.map(Result::unwrap).collect();
                let want: Vec<Pair> = (0..5u32)
                    .map(|i| Pair {
                        a: i + 100 * m as u32,
                        b: i as u16,
                    })
                    .collect();
                assert_eq!(got, want, "{format}, instance {m}");
            }
        }
    }

    #[test]
    fn a_row_refused_is_an_error_at_its_own_message_and_the_rows_after_it_still_come() {
        // Rows of 6 bytes read with the plan of a 7-byte format: every row's length
        // is wrong, and each error names the byte its own message starts at.
        let short = log("pair:uint32_t a;uint16_t b;", 4, 0, 0);
        let long = log("pair:uint32_t a;uint16_t b;uint8_t c;", 1, 0, 1);
        let short = ULog::parse(&short).unwrap();
        let long = ULog::parse(&long).unwrap();
        let plan = long.read::<Pair>(0).unwrap().plan().clone();
        let topic = short.topics().next().unwrap();
        let rows = TypedRows { topic, plan };
        let offsets: Vec<u64> = topic.message_offsets().iter().collect();
        assert_eq!(offsets.len(), 4);
        let errors: Vec<TypedError> = rows.iter().map(|r| r.unwrap_err()).collect();
        assert_eq!(errors.len(), 4, "every row handed out, none left out");
        for (e, offset) in errors.iter().zip(&offsets) {
            assert!(matches!(e.kind(), super::super::TypedErrorKind::Decode(_)));
            let text = e.to_string();
            assert!(
                text.contains(&format!("data message at byte {offset}")),
                "{text}"
            );
            assert!(text.contains("6"), "the row's length: {text}");
        }
        // `get` decodes by the plan, without the cursor: the same error.
        let error = rows.get(2).unwrap().unwrap_err().to_string();
        assert!(error.contains(&format!("data message at byte {}", offsets[2])));

        // A binding decoded from its wire bytes, not through the image: the same.
        let plan = long.read::<Plain>(0).unwrap().plan().clone();
        let rows = TypedRows { topic, plan };
        let errors: Vec<String> = rows.iter().map(|r| r.unwrap_err().to_string()).collect();
        assert_eq!(errors.len(), 4);
        for (e, offset) in errors.iter().zip(&offsets) {
            assert!(e.contains(&format!("data message at byte {offset}")), "{e}");
        }
    }

    #[test]
    fn a_binding_decoded_from_its_wire_bytes_reads_every_row() {
        let bytes = log("pair:uint32_t a;uint16_t b;", 3, 0, 0);
        let log = ULog::parse(&bytes).unwrap();
        let rows = log.read::<Plain>(0).unwrap();
        let got: Vec<Plain> = rows.iter().map(Result::unwrap).collect();
        let want: Vec<Plain> = (0..3u32).map(|i| Plain { a: i, b: i as u16 }).collect();
        assert_eq!(got, want);
    }
}
