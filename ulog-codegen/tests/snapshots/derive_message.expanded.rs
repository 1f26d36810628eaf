#[allow(non_snake_case, clippy::all)]
const _: () = {
    const __O0: usize = 0usize;
    const __S0: usize = 0usize;
    const __R0: usize = 0usize;
    const __O1: usize = __O0 + ::my_ulog::typed::__private::wire_size::<u64>();
    const __S1: usize = __S0 + 0usize + <u64 as ::my_ulog::typed::WireField>::OPTIONAL;
    const __R1: usize = __R0 + <u64 as ::my_ulog::typed::WireField>::SOURCES;
    const __O2: usize = __O1 + (4);
    const __S2: usize = __S1 + 0usize + 0usize;
    const __R2: usize = __R1 + 0usize;
    const __O3: usize = __O2
        + (::my_ulog::typed::__private::wire_size::<EscReport>() * (8));
    const __S3: usize = __S2 + 0usize
        + <EscReport as ::my_ulog::typed::WireField>::OPTIONAL;
    const __R3: usize = __R2
        + ::my_ulog::typed::__private::array_sources::<EscReport>(8);
    const __O4: usize = __O3 + ::my_ulog::typed::__private::wire_size::<CharArray<4>>();
    const __S4: usize = __S3 + 0usize
        + <CharArray<4> as ::my_ulog::typed::WireField>::OPTIONAL;
    const __R4: usize = __R3 + <CharArray<4> as ::my_ulog::typed::WireField>::SOURCES;
    const __SIZE: usize = __O4 + (2);
    const _: () = {
        ::my_ulog::typed::__private::assert_field::<u64>();
        ::my_ulog::typed::__private::assert_array_element::<EscReport>();
        ::my_ulog::typed::__private::assert_field::<CharArray<4>>();
    };
    #[automatically_derived]
    impl ::my_ulog::typed::WireField for Esc {
        type Wire = [u8; __SIZE];
        const KIND: ::my_ulog::typed::FieldKind = ::my_ulog::typed::FieldKind::Nested(
            <Self as ::my_ulog::ULogMessage>::schema,
        );
        const IS_WIRE: bool = ::core::mem::size_of::<Self>() == __SIZE
            && ::core::mem::align_of::<Self>() == 1
            && <u64 as ::my_ulog::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, timestamp) == __O0 && true
            && ::core::mem::offset_of!(Self, _padding0) == __O1
            && <EscReport as ::my_ulog::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, reports) == __O2
            && <CharArray<4> as ::my_ulog::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, label) == __O3 && true
            && ::core::mem::offset_of!(Self, code) == __O4;
        const OPTIONAL: usize = __S4 + 0usize + 0usize;
        type Writability = <<<::my_ulog::typed::Writable as ::my_ulog::typed::Writability>::And<
            <u64 as ::my_ulog::typed::WireField>::Writability,
        > as ::my_ulog::typed::Writability>::And<
            <EscReport as ::my_ulog::typed::WireField>::Writability,
        > as ::my_ulog::typed::Writability>::And<
            <CharArray<4> as ::my_ulog::typed::WireField>::Writability,
        >;
        const SOURCES: usize = __R4 + 1usize;
        const DIRECT: bool = true && <u64 as ::my_ulog::typed::WireField>::DIRECT && true
            && <EscReport as ::my_ulog::typed::WireField>::DIRECT
            && <CharArray<4> as ::my_ulog::typed::WireField>::DIRECT && true;
        #[inline]
        fn from_wire(
            wire: &[u8; __SIZE],
            present: ::my_ulog::typed::Present<'_>,
        ) -> Self {
            let _ = present;
            Self {
                timestamp: ::my_ulog::typed::__private::read::<
                    u64,
                >(
                    wire,
                    __O0,
                    present.sub(__S0, <u64 as ::my_ulog::typed::WireField>::OPTIONAL),
                ),
                _padding0: [0u8; 4],
                reports: ::my_ulog::typed::__private::read_array(
                    wire,
                    __O2,
                    present
                        .sub(__S2, <EscReport as ::my_ulog::typed::WireField>::OPTIONAL),
                ),
                label: ::my_ulog::typed::__private::read::<
                    CharArray<4>,
                >(
                    wire,
                    __O3,
                    present
                        .sub(
                            __S3,
                            <CharArray<4> as ::my_ulog::typed::WireField>::OPTIONAL,
                        ),
                ),
                code: ::my_ulog::typed::__private::read_array(
                    wire,
                    __O4,
                    ::my_ulog::typed::Present::ALL,
                ),
            }
        }
        #[inline]
        fn from_payload(
            payload: &[u8],
            sources: &[u32],
            present: ::my_ulog::typed::Present<'_>,
        ) -> Self {
            let _ = (payload, sources, present);
            Self {
                timestamp: ::my_ulog::typed::__private::read_source::<
                    u64,
                >(
                    payload,
                    sources,
                    __R0,
                    present.sub(__S0, <u64 as ::my_ulog::typed::WireField>::OPTIONAL),
                ),
                _padding0: [0u8; 4],
                reports: ::my_ulog::typed::__private::read_array_source(
                    payload,
                    sources,
                    __R2,
                    present
                        .sub(__S2, <EscReport as ::my_ulog::typed::WireField>::OPTIONAL),
                ),
                label: ::my_ulog::typed::__private::read_source::<
                    CharArray<4>,
                >(
                    payload,
                    sources,
                    __R3,
                    present
                        .sub(
                            __S3,
                            <CharArray<4> as ::my_ulog::typed::WireField>::OPTIONAL,
                        ),
                ),
                code: ::my_ulog::typed::__private::read_array_source(
                    payload,
                    sources,
                    __R4,
                    ::my_ulog::typed::Present::ALL,
                ),
            }
        }
        #[inline]
        fn to_wire(&self) -> [u8; __SIZE] {
            let mut wire = [0u8; __SIZE];
            ::my_ulog::typed::__private::write::<u64>(&mut wire, __O0, &self.timestamp);
            ::my_ulog::typed::__private::write_array::<
                EscReport,
            >(&mut wire, __O2, &self.reports);
            ::my_ulog::typed::__private::write::<
                CharArray<4>,
            >(&mut wire, __O3, &self.label);
            ::my_ulog::typed::__private::write_array::<u8>(&mut wire, __O4, &self.code);
            wire
        }
        fn visit(
            &self,
            path: &mut ::std::string::String,
            f: &mut dyn ::core::ops::FnMut(&str, ::my_ulog::typed::__private::Value<'_>),
        ) {
            <Self as ::my_ulog::ULogMessage>::visit_fields_at(self, path, f)
        }
    }
    #[automatically_derived]
    impl ::my_ulog::typed::ArrayElement for Esc {}
    #[automatically_derived]
    impl ::my_ulog::ULogMessage for Esc {
        const NAME: &'static str = "esc_status";
        const ALIASES: &'static [&'static str] = &[];
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
            SCHEMA
                .get_or_init(|| {
                    ::my_ulog::typed::Schema::build("esc_status", &FIELDS)
                        .with_rust_name("Esc", false)
                })
        }
        fn visit_fields_at(
            &self,
            path: &mut ::std::string::String,
            f: &mut dyn ::core::ops::FnMut(&str, ::my_ulog::typed::__private::Value<'_>),
        ) {
            let base = path.len();
            ::my_ulog::typed::__private::visit_field::<
                u64,
            >(&self.timestamp, path, base, "timestamp", f);
            ::my_ulog::typed::__private::visit_array::<
                EscReport,
            >(&self.reports, path, base, "esc", f);
            ::my_ulog::typed::__private::visit_field::<
                CharArray<4>,
            >(&self.label, path, base, "label", f);
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
};
