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
        <Self as ::ulog_core::typed::ULogMessage>::zeroed()
    }
}
#[allow(non_snake_case, clippy::all)]
const _: () = {
    #[repr(C)]
    #[derive(
        ::ulog_core::typed::__private::zerocopy::FromBytes,
        ::ulog_core::typed::__private::zerocopy::IntoBytes,
        ::ulog_core::typed::__private::zerocopy::KnownLayout,
        ::ulog_core::typed::__private::zerocopy::Immutable,
        ::ulog_core::typed::__private::zerocopy::Unaligned
    )]
    #[zerocopy(crate = "::ulog_core::typed::__private::zerocopy")]
    #[doc(hidden)]
    pub struct __UlogWire {
        timestamp: <u64 as ::ulog_core::typed::WireField>::Wire,
        q: [<f32 as ::ulog_core::typed::WireField>::Wire; 4usize],
        r#type: <u8 as ::ulog_core::typed::WireField>::Wire,
        name: <::ulog_core::typed::CharArray<
            3usize,
        > as ::ulog_core::typed::WireField>::Wire,
        _padding0: [u8; 4usize],
    }
    const _: () = {
        ::ulog_core::typed::__private::assert_field::<u64>();
        ::ulog_core::typed::__private::assert_array_element::<f32>();
        ::ulog_core::typed::__private::assert_field::<u8>();
        ::ulog_core::typed::__private::assert_field::<
            ::ulog_core::typed::CharArray<3usize>,
        >();
    };
    #[automatically_derived]
    impl ::ulog_core::typed::WireField for VehicleAttitude {
        type Wire = __UlogWire;
        const KIND: ::ulog_core::typed::FieldKind = ::ulog_core::typed::FieldKind::Nested(
            <Self as ::ulog_core::typed::ULogMessage>::schema,
        );
        const IS_WIRE: bool = ::core::mem::size_of::<Self>()
            == ::core::mem::size_of::<__UlogWire>()
            && ::core::mem::align_of::<Self>() == 1
            && <u64 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, timestamp)
                == ::core::mem::offset_of!(__UlogWire, timestamp)
            && <f32 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, q) == ::core::mem::offset_of!(__UlogWire, q)
            && <u8 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, r#type)
                == ::core::mem::offset_of!(__UlogWire, r#type)
            && <::ulog_core::typed::CharArray<
                3usize,
            > as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, name)
                == ::core::mem::offset_of!(__UlogWire, name) && true
            && ::core::mem::offset_of!(Self, _padding0)
                == ::core::mem::offset_of!(__UlogWire, _padding0);
        #[inline]
        fn from_wire(wire: &__UlogWire) -> Self {
            Self {
                timestamp: <u64 as ::ulog_core::typed::WireField>::from_wire(
                    &wire.timestamp,
                ),
                q: ::core::array::from_fn(|i| <f32 as ::ulog_core::typed::WireField>::from_wire(
                    &wire.q[i],
                )),
                r#type: <u8 as ::ulog_core::typed::WireField>::from_wire(&wire.r#type),
                name: <::ulog_core::typed::CharArray<
                    3usize,
                > as ::ulog_core::typed::WireField>::from_wire(&wire.name),
                _padding0: [0u8; 4usize],
            }
        }
        #[inline]
        fn to_wire(&self) -> __UlogWire {
            __UlogWire {
                timestamp: <u64 as ::ulog_core::typed::WireField>::to_wire(
                    &self.timestamp,
                ),
                q: ::core::array::from_fn(|i| <f32 as ::ulog_core::typed::WireField>::to_wire(
                    &self.q[i],
                )),
                r#type: <u8 as ::ulog_core::typed::WireField>::to_wire(&self.r#type),
                name: <::ulog_core::typed::CharArray<
                    3usize,
                > as ::ulog_core::typed::WireField>::to_wire(&self.name),
                _padding0: [0u8; 4usize],
            }
        }
        fn visit_values(
            &self,
            path: &mut ::std::string::String,
            f: &mut dyn ::core::ops::FnMut(
                &str,
                ::ulog_core::typed::__private::Value<'_>,
            ),
        ) {
            let base = path.len();
            ::ulog_core::typed::__private::visit_field(
                &self.timestamp,
                path,
                base,
                "timestamp",
                f,
            );
            ::ulog_core::typed::__private::visit_array(&self.q, path, base, "q", f);
            ::ulog_core::typed::__private::visit_field(
                &self.r#type,
                path,
                base,
                "type",
                f,
            );
            ::ulog_core::typed::__private::visit_field(
                &self.name,
                path,
                base,
                "name",
                f,
            );
        }
    }
    #[automatically_derived]
    impl ::ulog_core::typed::ArrayElement for VehicleAttitude {}
    #[automatically_derived]
    impl ::ulog_core::typed::ULogMessage for VehicleAttitude {
        const NAME: &'static str = "vehicle_attitude";
        fn schema() -> &'static ::ulog_core::typed::Schema {
            static FIELDS: [::ulog_core::typed::FieldDef; 5usize] = [
                ::ulog_core::typed::FieldDef::new(
                    "timestamp",
                    &[],
                    <u64 as ::ulog_core::typed::WireField>::KIND,
                    <u64 as ::ulog_core::typed::WireField>::COUNT,
                ),
                ::ulog_core::typed::FieldDef::new(
                    "q",
                    &[],
                    <f32 as ::ulog_core::typed::WireField>::KIND,
                    ::core::option::Option::Some(4usize),
                ),
                ::ulog_core::typed::FieldDef::new(
                    "type",
                    &[],
                    <u8 as ::ulog_core::typed::WireField>::KIND,
                    <u8 as ::ulog_core::typed::WireField>::COUNT,
                ),
                ::ulog_core::typed::FieldDef::new(
                    "name",
                    &[],
                    <::ulog_core::typed::CharArray<
                        3usize,
                    > as ::ulog_core::typed::WireField>::KIND,
                    <::ulog_core::typed::CharArray<
                        3usize,
                    > as ::ulog_core::typed::WireField>::COUNT,
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
                .get_or_init(|| ::ulog_core::typed::Schema::build(
                    "vehicle_attitude",
                    &FIELDS,
                ))
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
        <Self as ::ulog_core::typed::ULogMessage>::zeroed()
    }
}
#[allow(non_snake_case, clippy::all)]
const _: () = {
    #[repr(C)]
    #[derive(
        ::ulog_core::typed::__private::zerocopy::FromBytes,
        ::ulog_core::typed::__private::zerocopy::IntoBytes,
        ::ulog_core::typed::__private::zerocopy::KnownLayout,
        ::ulog_core::typed::__private::zerocopy::Immutable,
        ::ulog_core::typed::__private::zerocopy::Unaligned
    )]
    #[zerocopy(crate = "::ulog_core::typed::__private::zerocopy")]
    #[doc(hidden)]
    pub struct __UlogWire {
        both: [<VehicleAttitude as ::ulog_core::typed::WireField>::Wire; 2usize],
    }
    const _: () = {
        ::ulog_core::typed::__private::assert_array_element::<VehicleAttitude>();
    };
    #[automatically_derived]
    impl ::ulog_core::typed::WireField for Pair {
        type Wire = __UlogWire;
        const KIND: ::ulog_core::typed::FieldKind = ::ulog_core::typed::FieldKind::Nested(
            <Self as ::ulog_core::typed::ULogMessage>::schema,
        );
        const IS_WIRE: bool = ::core::mem::size_of::<Self>()
            == ::core::mem::size_of::<__UlogWire>()
            && ::core::mem::align_of::<Self>() == 1
            && <VehicleAttitude as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, both)
                == ::core::mem::offset_of!(__UlogWire, both);
        #[inline]
        fn from_wire(wire: &__UlogWire) -> Self {
            Self {
                both: ::core::array::from_fn(|i| <VehicleAttitude as ::ulog_core::typed::WireField>::from_wire(
                    &wire.both[i],
                )),
            }
        }
        #[inline]
        fn to_wire(&self) -> __UlogWire {
            __UlogWire {
                both: ::core::array::from_fn(|i| <VehicleAttitude as ::ulog_core::typed::WireField>::to_wire(
                    &self.both[i],
                )),
            }
        }
        fn visit_values(
            &self,
            path: &mut ::std::string::String,
            f: &mut dyn ::core::ops::FnMut(
                &str,
                ::ulog_core::typed::__private::Value<'_>,
            ),
        ) {
            let base = path.len();
            ::ulog_core::typed::__private::visit_array(
                &self.both,
                path,
                base,
                "both",
                f,
            );
        }
    }
    #[automatically_derived]
    impl ::ulog_core::typed::ArrayElement for Pair {}
    #[automatically_derived]
    impl ::ulog_core::typed::ULogMessage for Pair {
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
            SCHEMA.get_or_init(|| ::ulog_core::typed::Schema::build("pair", &FIELDS))
        }
    }
};
