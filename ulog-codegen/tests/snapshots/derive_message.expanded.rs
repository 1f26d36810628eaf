#[allow(non_snake_case, clippy::all)]
const _: () = {
    #[repr(C)]
    #[derive(
        ::my_ulog::typed::__private::zerocopy::FromBytes,
        ::my_ulog::typed::__private::zerocopy::IntoBytes,
        ::my_ulog::typed::__private::zerocopy::KnownLayout,
        ::my_ulog::typed::__private::zerocopy::Immutable,
        ::my_ulog::typed::__private::zerocopy::Unaligned
    )]
    #[zerocopy(crate = "::my_ulog::typed::__private::zerocopy")]
    #[doc(hidden)]
    pub struct __UlogWire {
        timestamp: <u64 as ::my_ulog::typed::WireField>::Wire,
        _padding0: [u8; 4],
        reports: [<EscReport as ::my_ulog::typed::WireField>::Wire; 8],
        label: <CharArray<4> as ::my_ulog::typed::WireField>::Wire,
        code: [u8; 2],
    }
    const _: () = {
        ::my_ulog::typed::__private::assert_field::<u64>();
        ::my_ulog::typed::__private::assert_array_element::<EscReport>();
        ::my_ulog::typed::__private::assert_field::<CharArray<4>>();
    };
    #[automatically_derived]
    impl ::my_ulog::typed::WireField for Esc {
        type Wire = __UlogWire;
        const KIND: ::my_ulog::typed::FieldKind = ::my_ulog::typed::FieldKind::Nested(
            <Self as ::my_ulog::typed::ULogMessage>::schema,
        );
        const IS_WIRE: bool = ::core::mem::size_of::<Self>()
            == ::core::mem::size_of::<__UlogWire>()
            && ::core::mem::align_of::<Self>() == 1
            && <u64 as ::my_ulog::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, timestamp)
                == ::core::mem::offset_of!(__UlogWire, timestamp) && true
            && ::core::mem::offset_of!(Self, _padding0)
                == ::core::mem::offset_of!(__UlogWire, _padding0)
            && <EscReport as ::my_ulog::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, reports)
                == ::core::mem::offset_of!(__UlogWire, reports)
            && <CharArray<4> as ::my_ulog::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, label)
                == ::core::mem::offset_of!(__UlogWire, label) && true
            && ::core::mem::offset_of!(Self, code)
                == ::core::mem::offset_of!(__UlogWire, code);
        #[inline]
        fn from_wire(wire: &__UlogWire) -> Self {
            Self {
                timestamp: <u64 as ::my_ulog::typed::WireField>::from_wire(
                    &wire.timestamp,
                ),
                _padding0: [0u8; 4],
                reports: ::core::array::from_fn(|i| <EscReport as ::my_ulog::typed::WireField>::from_wire(
                    &wire.reports[i],
                )),
                label: <CharArray<
                    4,
                > as ::my_ulog::typed::WireField>::from_wire(&wire.label),
                code: wire.code,
            }
        }
        #[inline]
        fn to_wire(&self) -> __UlogWire {
            __UlogWire {
                timestamp: <u64 as ::my_ulog::typed::WireField>::to_wire(
                    &self.timestamp,
                ),
                _padding0: [0u8; 4],
                reports: ::core::array::from_fn(|i| <EscReport as ::my_ulog::typed::WireField>::to_wire(
                    &self.reports[i],
                )),
                label: <CharArray<
                    4,
                > as ::my_ulog::typed::WireField>::to_wire(&self.label),
                code: self.code,
            }
        }
        fn visit_values(
            &self,
            path: &mut ::std::string::String,
            f: &mut dyn ::core::ops::FnMut(&str, ::my_ulog::typed::__private::Value<'_>),
        ) {
            let base = path.len();
            ::my_ulog::typed::__private::visit_field(
                &self.timestamp,
                path,
                base,
                "timestamp",
                f,
            );
            ::my_ulog::typed::__private::visit_array(
                &self.reports,
                path,
                base,
                "esc",
                f,
            );
            ::my_ulog::typed::__private::visit_field(
                &self.label,
                path,
                base,
                "label",
                f,
            );
            ::my_ulog::typed::__private::visit_chars(
                &self.code,
                false,
                path,
                base,
                "code",
                f,
            );
        }
    }
    #[automatically_derived]
    impl ::my_ulog::typed::ArrayElement for Esc {}
    #[automatically_derived]
    impl ::my_ulog::typed::ULogMessage for Esc {
        const NAME: &'static str = "esc_status";
        fn schema() -> &'static ::my_ulog::typed::Schema {
            static FIELDS: [::my_ulog::typed::FieldDef; 5usize] = [
                ::my_ulog::typed::FieldDef::new(
                    "timestamp",
                    &[],
                    <u64 as ::my_ulog::typed::WireField>::KIND,
                    <u64 as ::my_ulog::typed::WireField>::COUNT,
                ),
                ::my_ulog::typed::FieldDef::new(
                    "_padding0",
                    &[],
                    ::my_ulog::typed::FieldKind::Basic(
                        ::my_ulog::typed::__private::BasicType::UInt8,
                    ),
                    ::core::option::Option::Some(4),
                ),
                ::my_ulog::typed::FieldDef::new(
                    "esc",
                    &["escs"],
                    <EscReport as ::my_ulog::typed::WireField>::KIND,
                    ::core::option::Option::Some(8),
                ),
                ::my_ulog::typed::FieldDef::new(
                    "label",
                    &[],
                    <CharArray<4> as ::my_ulog::typed::WireField>::KIND,
                    <CharArray<4> as ::my_ulog::typed::WireField>::COUNT,
                ),
                ::my_ulog::typed::FieldDef::new(
                    "code",
                    &[],
                    ::my_ulog::typed::FieldKind::Basic(
                        ::my_ulog::typed::__private::BasicType::Char,
                    ),
                    ::core::option::Option::Some(2),
                ),
            ];
            static SCHEMA: ::my_ulog::typed::__private::OnceLock<
                ::my_ulog::typed::Schema,
            > = ::my_ulog::typed::__private::OnceLock::new();
            SCHEMA.get_or_init(|| ::my_ulog::typed::Schema::build("esc_status", &FIELDS))
        }
    }
};
