#[allow(non_snake_case, clippy::all)]
const _: () = {
    const __O0: usize = 0usize;
    const __S0: usize = 0usize;
    const __R0: usize = 0usize;
    const __O1: usize = __O0 + ::ulog_core::typed::__private::wire_size::<le::U64>();
    const __S1: usize = __S0 + 0usize
        + <le::U64 as ::ulog_core::typed::WireField>::OPTIONAL;
    const __R1: usize = __R0 + <le::U64 as ::ulog_core::typed::WireField>::SOURCES;
    const __O2: usize = __O1
        + (::ulog_core::typed::__private::wire_size::<le::F32>() * (4));
    const __S2: usize = __S1 + 0usize
        + <le::F32 as ::ulog_core::typed::WireField>::OPTIONAL;
    const __R2: usize = __R1
        + ::ulog_core::typed::__private::array_sources::<le::F32>(4);
    const __SIZE: usize = __O2 + ::ulog_core::typed::__private::wire_size::<u8>();
    const _: () = {
        ::ulog_core::typed::__private::assert_field::<le::U64>();
        ::ulog_core::typed::__private::assert_array_element::<le::F32>();
        ::ulog_core::typed::__private::assert_field::<u8>();
    };
    #[automatically_derived]
    impl ::ulog_core::typed::WireField for Attitude {
        type Wire = [u8; __SIZE];
        const KIND: ::ulog_core::typed::FieldKind = ::ulog_core::typed::FieldKind::Nested(
            <Self as ::ulog_core::ULogMessage>::schema,
        );
        const IS_WIRE: bool = ::core::mem::size_of::<Self>() == __SIZE
            && ::core::mem::align_of::<Self>() == 1
            && <le::U64 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, timestamp) == __O0
            && <le::F32 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, q) == __O1
            && <u8 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, reset) == __O2;
        const OPTIONAL: usize = __S2 + 0usize
            + <u8 as ::ulog_core::typed::WireField>::OPTIONAL;
        type Writability = <<<::ulog_core::typed::Writable as ::ulog_core::typed::Writability>::And<
            <le::U64 as ::ulog_core::typed::WireField>::Writability,
        > as ::ulog_core::typed::Writability>::And<
            <le::F32 as ::ulog_core::typed::WireField>::Writability,
        > as ::ulog_core::typed::Writability>::And<
            <u8 as ::ulog_core::typed::WireField>::Writability,
        >;
        const SOURCES: usize = __R2 + <u8 as ::ulog_core::typed::WireField>::SOURCES;
        const DIRECT: bool = true && <le::U64 as ::ulog_core::typed::WireField>::DIRECT
            && <le::F32 as ::ulog_core::typed::WireField>::DIRECT
            && <u8 as ::ulog_core::typed::WireField>::DIRECT;
        #[inline]
        fn from_wire(
            wire: &[u8; __SIZE],
            present: ::ulog_core::typed::Present<'_>,
        ) -> Self {
            let _ = present;
            Self {
                timestamp: ::ulog_core::typed::__private::read::<
                    le::U64,
                >(
                    wire,
                    __O0,
                    present
                        .sub(__S0, <le::U64 as ::ulog_core::typed::WireField>::OPTIONAL),
                ),
                q: ::ulog_core::typed::__private::read_array(
                    wire,
                    __O1,
                    present
                        .sub(__S1, <le::F32 as ::ulog_core::typed::WireField>::OPTIONAL),
                ),
                reset: ::ulog_core::typed::__private::read::<
                    u8,
                >(
                    wire,
                    __O2,
                    present.sub(__S2, <u8 as ::ulog_core::typed::WireField>::OPTIONAL),
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
                timestamp: ::ulog_core::typed::__private::read_source::<
                    le::U64,
                >(
                    payload,
                    sources,
                    __R0,
                    present
                        .sub(__S0, <le::U64 as ::ulog_core::typed::WireField>::OPTIONAL),
                ),
                q: ::ulog_core::typed::__private::read_array_source(
                    payload,
                    sources,
                    __R1,
                    present
                        .sub(__S1, <le::F32 as ::ulog_core::typed::WireField>::OPTIONAL),
                ),
                reset: ::ulog_core::typed::__private::read_source::<
                    u8,
                >(
                    payload,
                    sources,
                    __R2,
                    present.sub(__S2, <u8 as ::ulog_core::typed::WireField>::OPTIONAL),
                ),
            }
        }
        #[inline]
        fn to_wire(&self) -> [u8; __SIZE] {
            let mut wire = [0u8; __SIZE];
            ::ulog_core::typed::__private::write::<
                le::U64,
            >(&mut wire, __O0, &self.timestamp);
            ::ulog_core::typed::__private::write_array::<
                le::F32,
            >(&mut wire, __O1, &self.q);
            ::ulog_core::typed::__private::write::<u8>(&mut wire, __O2, &self.reset);
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
    impl ::ulog_core::typed::ArrayElement for Attitude {}
    #[automatically_derived]
    impl ::ulog_core::ULogMessage for Attitude {
        const NAME: &'static str = "vehicle_attitude";
        const ALIASES: &'static [&'static str] = &[];
        fn schema() -> &'static ::ulog_core::typed::Schema {
            static FIELDS: [::ulog_core::typed::FieldDef; 3usize] = [
                ::ulog_core::typed::FieldDef::new(
                    "timestamp",
                    &[],
                    <le::U64 as ::ulog_core::typed::WireField>::KIND,
                    <le::U64 as ::ulog_core::typed::WireField>::COUNT,
                ),
                ::ulog_core::typed::FieldDef::new(
                    "q",
                    &[],
                    <le::F32 as ::ulog_core::typed::WireField>::KIND,
                    ::core::option::Option::Some(4),
                ),
                ::ulog_core::typed::FieldDef::new(
                    "reset",
                    &[],
                    <u8 as ::ulog_core::typed::WireField>::KIND,
                    <u8 as ::ulog_core::typed::WireField>::COUNT,
                ),
            ];
            static SCHEMA: ::ulog_core::typed::__private::OnceLock<
                ::ulog_core::typed::Schema,
            > = ::ulog_core::typed::__private::OnceLock::new();
            SCHEMA
                .get_or_init(|| {
                    ::ulog_core::typed::Schema::build("vehicle_attitude", &FIELDS)
                        .with_rust_name("Attitude", false)
                })
        }
        fn visit_fields_at(
            &self,
            path: &mut ::std::string::String,
            f: &mut dyn ::core::ops::FnMut(
                &str,
                ::ulog_core::typed::__private::Value<'_>,
            ),
        ) {
            let base = path.len();
            ::ulog_core::typed::__private::visit_field::<
                le::U64,
            >(&self.timestamp, path, base, "timestamp", f);
            ::ulog_core::typed::__private::visit_array::<
                le::F32,
            >(&self.q, path, base, "q", f);
            ::ulog_core::typed::__private::visit_field::<
                u8,
            >(&self.reset, path, base, "reset", f);
        }
    }
    const _: () = ::core::assert!(
        < Attitude as ::ulog_core::typed::WireField > ::IS_WIRE,
        "`Attitude` is not its wire image, so it cannot be a view: its fields must be `u8`, `i8`, `CharArray<N>`, `ulog_core::typed::le` types, arrays of these or nested view bindings, laid out in declaration order (add `#[repr(C)]`)"
    );
    #[automatically_derived]
    unsafe impl ::ulog_core::typed::WireImage for Attitude {}
};
