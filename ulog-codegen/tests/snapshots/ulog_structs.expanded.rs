/// The ULog message `vehicle_attitude`:
///
///```text
/// vehicle_attitude:uint64_t timestamp;float[4] q;uint8_t type;char[3] name;uint8_t[4] _padding0;
///```
#[derive(
    ::core::fmt::Debug,
    ::core::clone::Clone,
    ::core::marker::Copy,
    ::core::cmp::PartialEq
)]
#[allow(non_snake_case, non_camel_case_types)]
pub struct VehicleAttitude {
    /// `timestamp`
    pub timestamp: u64,
    /// `q`
    pub q: [f32; 4usize],
    /// `type`
    pub r#type: u8,
    /// `name`
    pub name: ::ulog_core::typed::CharArray<3usize>,
    /// `_padding0`
    pub _padding0: [u8; 4usize],
}
#[automatically_derived]
impl ::core::default::Default for VehicleAttitude {
    /// Every field zero.
    fn default() -> Self {
        <Self as ::ulog_core::ULogMessage>::zeroed()
    }
}
#[allow(non_snake_case, clippy::all)]
const _: () = {
    const __R0: usize = 0usize;
    const __R1: usize = __R0 + <u64 as ::ulog_core::typed::WireField>::SOURCES;
    const __R2: usize = __R1
        + ::ulog_core::typed::__private::array_sources::<f32>(4usize);
    const __R3: usize = __R2 + <u8 as ::ulog_core::typed::WireField>::SOURCES;
    const __R4: usize = __R3
        + <::ulog_core::typed::CharArray<
            3usize,
        > as ::ulog_core::typed::WireField>::SOURCES;
    #[automatically_derived]
    impl ::ulog_core::typed::WireField for VehicleAttitude {
        type Wire = [u8; 32usize];
        const KIND: ::ulog_core::typed::FieldKind = ::ulog_core::typed::FieldKind::Nested(
            <Self as ::ulog_core::ULogMessage>::schema,
        );
        const IS_WIRE: bool = false;
        const OPTIONAL: usize = 0usize;
        type Writability = ::ulog_core::typed::Writable;
        const SOURCES: usize = __R4 + 0usize;
        const DIRECT: bool = true && <u64 as ::ulog_core::typed::WireField>::DIRECT
            && <f32 as ::ulog_core::typed::WireField>::DIRECT
            && <u8 as ::ulog_core::typed::WireField>::DIRECT
            && <::ulog_core::typed::CharArray<
                3usize,
            > as ::ulog_core::typed::WireField>::DIRECT && true;
        #[inline]
        fn from_wire(
            wire: &[u8; 32usize],
            present: ::ulog_core::typed::Present<'_>,
        ) -> Self {
            let _ = present;
            Self {
                timestamp: ::ulog_core::typed::__private::read::<
                    u64,
                >(wire, 0usize, ::ulog_core::typed::Present::ALL),
                q: ::ulog_core::typed::__private::read_array(
                    wire,
                    8usize,
                    ::ulog_core::typed::Present::ALL,
                ),
                r#type: ::ulog_core::typed::__private::read::<
                    u8,
                >(wire, 24usize, ::ulog_core::typed::Present::ALL),
                name: ::ulog_core::typed::__private::read::<
                    ::ulog_core::typed::CharArray<3usize>,
                >(wire, 25usize, ::ulog_core::typed::Present::ALL),
                _padding0: [0u8; 4usize],
            }
        }
        #[inline]
        fn from_payload(
            payload: &[u8],
            sources: &[u32],
            present: ::ulog_core::typed::Present<'_>,
        ) -> Self {
            let _ = (payload, sources, present);
            Self {
                timestamp: ::ulog_core::typed::__private::read_source::<
                    u64,
                >(payload, sources, __R0, ::ulog_core::typed::Present::ALL),
                q: ::ulog_core::typed::__private::read_array_source(
                    payload,
                    sources,
                    __R1,
                    ::ulog_core::typed::Present::ALL,
                ),
                r#type: ::ulog_core::typed::__private::read_source::<
                    u8,
                >(payload, sources, __R2, ::ulog_core::typed::Present::ALL),
                name: ::ulog_core::typed::__private::read_source::<
                    ::ulog_core::typed::CharArray<3usize>,
                >(payload, sources, __R3, ::ulog_core::typed::Present::ALL),
                _padding0: [0u8; 4usize],
            }
        }
        #[inline]
        fn to_wire(&self) -> [u8; 32usize] {
            let mut wire = [0u8; 32usize];
            ::ulog_core::typed::__private::write::<
                u64,
            >(&mut wire, 0usize, &self.timestamp);
            ::ulog_core::typed::__private::write_array::<
                f32,
            >(&mut wire, 8usize, &self.q);
            ::ulog_core::typed::__private::write::<u8>(&mut wire, 24usize, &self.r#type);
            ::ulog_core::typed::__private::write::<
                ::ulog_core::typed::CharArray<3usize>,
            >(&mut wire, 25usize, &self.name);
            wire
        }
        fn visit(
            &self,
            path: &mut ::std::string::String,
            f: &mut dyn ::core::ops::FnMut(
                &str,
                ::ulog_core::typed::__private::Value<'_>,
            ),
        ) {
            <Self as ::ulog_core::ULogMessage>::visit_fields_at(self, path, f)
        }
    }
    #[automatically_derived]
    impl ::ulog_core::typed::ArrayElement for VehicleAttitude {}
    #[automatically_derived]
    impl ::ulog_core::ULogMessage for VehicleAttitude {
        const NAME: &'static str = "vehicle_attitude";
        fn schema() -> &'static ::ulog_core::typed::Schema {
            static FIELDS: [::ulog_core::typed::FieldDef; 5usize] = [
                ::ulog_core::typed::FieldDef::new(
                    "timestamp",
                    &[],
                    ::ulog_core::typed::FieldKind::Basic(
                        ::ulog_core::typed::__private::BasicType::UInt64,
                    ),
                    ::core::option::Option::None,
                ),
                ::ulog_core::typed::FieldDef::new(
                    "q",
                    &[],
                    ::ulog_core::typed::FieldKind::Basic(
                        ::ulog_core::typed::__private::BasicType::Float,
                    ),
                    ::core::option::Option::Some(4usize),
                ),
                ::ulog_core::typed::FieldDef::new(
                    "type",
                    &[],
                    ::ulog_core::typed::FieldKind::Basic(
                        ::ulog_core::typed::__private::BasicType::UInt8,
                    ),
                    ::core::option::Option::None,
                ),
                ::ulog_core::typed::FieldDef::new(
                    "name",
                    &[],
                    ::ulog_core::typed::FieldKind::Basic(
                        ::ulog_core::typed::__private::BasicType::Char,
                    ),
                    ::core::option::Option::Some(3usize),
                ),
                ::ulog_core::typed::FieldDef::new(
                    "_padding0",
                    &[],
                    ::ulog_core::typed::FieldKind::Basic(
                        ::ulog_core::typed::__private::BasicType::UInt8,
                    ),
                    ::core::option::Option::Some(4usize),
                ),
            ];
            static SCHEMA: ::ulog_core::typed::__private::OnceLock<
                ::ulog_core::typed::Schema,
            > = ::ulog_core::typed::__private::OnceLock::new();
            SCHEMA
                .get_or_init(|| {
                    ::ulog_core::typed::Schema::build("vehicle_attitude", &FIELDS)
                        .with_rust_name("VehicleAttitude", false)
                })
        }
    }
};
/// The ULog message `pair`:
///
///```text
/// pair:vehicle_attitude[2] both;
///```
#[derive(
    ::core::fmt::Debug,
    ::core::clone::Clone,
    ::core::marker::Copy,
    ::core::cmp::PartialEq
)]
#[allow(non_snake_case, non_camel_case_types)]
pub struct Pair {
    /// `both`
    pub both: [VehicleAttitude; 2usize],
}
#[automatically_derived]
impl ::core::default::Default for Pair {
    /// Every field zero.
    fn default() -> Self {
        <Self as ::ulog_core::ULogMessage>::zeroed()
    }
}
#[allow(non_snake_case, clippy::all)]
const _: () = {
    const __R0: usize = 0usize;
    #[automatically_derived]
    impl ::ulog_core::typed::WireField for Pair {
        type Wire = [u8; 64usize];
        const KIND: ::ulog_core::typed::FieldKind = ::ulog_core::typed::FieldKind::Nested(
            <Self as ::ulog_core::ULogMessage>::schema,
        );
        const IS_WIRE: bool = false;
        const OPTIONAL: usize = 0usize;
        type Writability = ::ulog_core::typed::Writable;
        const SOURCES: usize = __R0
            + ::ulog_core::typed::__private::array_sources::<VehicleAttitude>(2usize);
        const DIRECT: bool = true
            && <VehicleAttitude as ::ulog_core::typed::WireField>::DIRECT;
        #[inline]
        fn from_wire(
            wire: &[u8; 64usize],
            present: ::ulog_core::typed::Present<'_>,
        ) -> Self {
            let _ = present;
            Self {
                both: ::ulog_core::typed::__private::read_array(
                    wire,
                    0usize,
                    ::ulog_core::typed::Present::ALL,
                ),
            }
        }
        #[inline]
        fn from_payload(
            payload: &[u8],
            sources: &[u32],
            present: ::ulog_core::typed::Present<'_>,
        ) -> Self {
            let _ = (payload, sources, present);
            Self {
                both: ::ulog_core::typed::__private::read_array_source(
                    payload,
                    sources,
                    __R0,
                    ::ulog_core::typed::Present::ALL,
                ),
            }
        }
        #[inline]
        fn to_wire(&self) -> [u8; 64usize] {
            let mut wire = [0u8; 64usize];
            ::ulog_core::typed::__private::write_array::<
                VehicleAttitude,
            >(&mut wire, 0usize, &self.both);
            wire
        }
        fn visit(
            &self,
            path: &mut ::std::string::String,
            f: &mut dyn ::core::ops::FnMut(
                &str,
                ::ulog_core::typed::__private::Value<'_>,
            ),
        ) {
            <Self as ::ulog_core::ULogMessage>::visit_fields_at(self, path, f)
        }
    }
    #[automatically_derived]
    impl ::ulog_core::typed::ArrayElement for Pair {}
    #[automatically_derived]
    impl ::ulog_core::ULogMessage for Pair {
        const NAME: &'static str = "pair";
        fn schema() -> &'static ::ulog_core::typed::Schema {
            static FIELDS: [::ulog_core::typed::FieldDef; 1usize] = [
                ::ulog_core::typed::FieldDef::new(
                    "both",
                    &[],
                    <VehicleAttitude as ::ulog_core::typed::WireField>::KIND,
                    ::core::option::Option::Some(2usize),
                ),
            ];
            static SCHEMA: ::ulog_core::typed::__private::OnceLock<
                ::ulog_core::typed::Schema,
            > = ::ulog_core::typed::__private::OnceLock::new();
            SCHEMA
                .get_or_init(|| {
                    ::ulog_core::typed::Schema::build("pair", &FIELDS)
                        .with_rust_name("Pair", false)
                })
        }
    }
};
