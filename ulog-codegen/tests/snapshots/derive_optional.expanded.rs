#[allow(non_snake_case, clippy::all)]
const _: () = {
    const __O0: usize = 0usize;
    const __S0: usize = 0usize;
    const __R0: usize = 0usize;
    const __O1: usize = __O0 + ::ulog_core::typed::__private::wire_size::<u64>();
    const __S1: usize = __S0 + 0usize + <u64 as ::ulog_core::typed::WireField>::OPTIONAL;
    const __R1: usize = __R0 + <u64 as ::ulog_core::typed::WireField>::SOURCES;
    const __O2: usize = __O1 + ::ulog_core::typed::__private::wire_size::<i32>();
    const __S2: usize = __S1 + 1usize + <i32 as ::ulog_core::typed::WireField>::OPTIONAL;
    const __R2: usize = __R1 + <i32 as ::ulog_core::typed::WireField>::SOURCES;
    const __O3: usize = __O2 + ::ulog_core::typed::__private::wire_size::<f64>();
    const __S3: usize = __S2 + 1usize + <f64 as ::ulog_core::typed::WireField>::OPTIONAL;
    const __R3: usize = __R2 + <f64 as ::ulog_core::typed::WireField>::SOURCES;
    const __O4: usize = __O3 + ::ulog_core::typed::__private::wire_size::<u8>();
    const __S4: usize = __S3 + 1usize + <u8 as ::ulog_core::typed::WireField>::OPTIONAL;
    const __R4: usize = __R3 + <u8 as ::ulog_core::typed::WireField>::SOURCES;
    const __O5: usize = __O4 + ::ulog_core::typed::__private::wire_size::<f32>();
    const __S5: usize = __S4 + 1usize + <f32 as ::ulog_core::typed::WireField>::OPTIONAL;
    const __R5: usize = __R4 + <f32 as ::ulog_core::typed::WireField>::SOURCES;
    const __SIZE: usize = __O5
        + (::ulog_core::typed::__private::wire_size::<Inner>() * (2));
    const _: () = {
        ::ulog_core::typed::__private::assert_field::<u64>();
        ::ulog_core::typed::__private::assert_field::<i32>();
        ::ulog_core::typed::__private::assert_field::<f64>();
        ::ulog_core::typed::__private::assert_field::<u8>();
        ::ulog_core::typed::__private::assert_field::<f32>();
        ::ulog_core::typed::__private::assert_array_element::<Inner>();
    };
    #[automatically_derived]
    impl ::ulog_core::typed::WireField for GpsFix {
        type Wire = [u8; __SIZE];
        const KIND: ::ulog_core::typed::FieldKind = ::ulog_core::typed::FieldKind::Nested(
            <Self as ::ulog_core::ULogMessage>::schema,
        );
        const IS_WIRE: bool = ::core::mem::size_of::<Self>() == __SIZE
            && ::core::mem::align_of::<Self>() == 1
            && <u64 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, timestamp) == __O0 && false
            && ::core::mem::offset_of!(Self, latitude) == __O1 && false
            && ::core::mem::offset_of!(Self, latitude_deg) == __O2
            && <u8 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, satellites_used) == __O3
            && <f32 as ::ulog_core::typed::WireField>::IS_WIRE
            && ::core::mem::offset_of!(Self, eph) == __O4 && false
            && ::core::mem::offset_of!(Self, nested) == __O5;
        const OPTIONAL: usize = __S5 + 1usize
            + <Inner as ::ulog_core::typed::WireField>::OPTIONAL;
        type Writability = ::ulog_core::typed::HasOptionFields;
        const SOURCES: usize = __R5
            + ::ulog_core::typed::__private::array_sources::<Inner>(2);
        const DIRECT: bool = true && <u64 as ::ulog_core::typed::WireField>::DIRECT
            && <i32 as ::ulog_core::typed::WireField>::DIRECT
            && <f64 as ::ulog_core::typed::WireField>::DIRECT
            && <u8 as ::ulog_core::typed::WireField>::DIRECT
            && <f32 as ::ulog_core::typed::WireField>::DIRECT
            && <Inner as ::ulog_core::typed::WireField>::DIRECT;
        #[inline]
        fn from_wire(
            wire: &[u8; __SIZE],
            present: ::ulog_core::typed::Present<'_>,
        ) -> Self {
            let _ = present;
            Self {
                timestamp: ::ulog_core::typed::__private::read::<
                    u64,
                >(
                    wire,
                    __O0,
                    present.sub(__S0, <u64 as ::ulog_core::typed::WireField>::OPTIONAL),
                ),
                latitude: if present.get(__S1) {
                    ::core::option::Option::Some(
                        ::ulog_core::typed::__private::read::<
                            i32,
                        >(
                            wire,
                            __O1,
                            present
                                .sub(
                                    __S1 + 1,
                                    <i32 as ::ulog_core::typed::WireField>::OPTIONAL,
                                ),
                        ),
                    )
                } else {
                    ::core::option::Option::None
                },
                latitude_deg: if present.get(__S2) {
                    ::core::option::Option::Some(
                        ::ulog_core::typed::__private::read::<
                            f64,
                        >(
                            wire,
                            __O2,
                            present
                                .sub(
                                    __S2 + 1,
                                    <f64 as ::ulog_core::typed::WireField>::OPTIONAL,
                                ),
                        ),
                    )
                } else {
                    ::core::option::Option::None
                },
                satellites_used: if present.get(__S3) {
                    ::ulog_core::typed::__private::read::<
                        u8,
                    >(
                        wire,
                        __O3,
                        present
                            .sub(
                                __S3 + 1,
                                <u8 as ::ulog_core::typed::WireField>::OPTIONAL,
                            ),
                    )
                } else {
                    ::core::default::Default::default()
                },
                eph: if present.get(__S4) {
                    ::ulog_core::typed::__private::read::<
                        f32,
                    >(
                        wire,
                        __O4,
                        present
                            .sub(
                                __S4 + 1,
                                <f32 as ::ulog_core::typed::WireField>::OPTIONAL,
                            ),
                    )
                } else {
                    99.0
                },
                nested: if present.get(__S5) {
                    ::core::option::Option::Some(
                        ::ulog_core::typed::__private::read_array(
                            wire,
                            __O5,
                            present
                                .sub(
                                    __S5 + 1,
                                    <Inner as ::ulog_core::typed::WireField>::OPTIONAL,
                                ),
                        ),
                    )
                } else {
                    ::core::option::Option::None
                },
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
                >(
                    payload,
                    sources,
                    __R0,
                    present.sub(__S0, <u64 as ::ulog_core::typed::WireField>::OPTIONAL),
                ),
                latitude: if present.get(__S1) {
                    ::core::option::Option::Some(
                        ::ulog_core::typed::__private::read_source::<
                            i32,
                        >(
                            payload,
                            sources,
                            __R1,
                            present
                                .sub(
                                    __S1 + 1,
                                    <i32 as ::ulog_core::typed::WireField>::OPTIONAL,
                                ),
                        ),
                    )
                } else {
                    ::core::option::Option::None
                },
                latitude_deg: if present.get(__S2) {
                    ::core::option::Option::Some(
                        ::ulog_core::typed::__private::read_source::<
                            f64,
                        >(
                            payload,
                            sources,
                            __R2,
                            present
                                .sub(
                                    __S2 + 1,
                                    <f64 as ::ulog_core::typed::WireField>::OPTIONAL,
                                ),
                        ),
                    )
                } else {
                    ::core::option::Option::None
                },
                satellites_used: if present.get(__S3) {
                    ::ulog_core::typed::__private::read_source::<
                        u8,
                    >(
                        payload,
                        sources,
                        __R3,
                        present
                            .sub(
                                __S3 + 1,
                                <u8 as ::ulog_core::typed::WireField>::OPTIONAL,
                            ),
                    )
                } else {
                    ::core::default::Default::default()
                },
                eph: if present.get(__S4) {
                    ::ulog_core::typed::__private::read_source::<
                        f32,
                    >(
                        payload,
                        sources,
                        __R4,
                        present
                            .sub(
                                __S4 + 1,
                                <f32 as ::ulog_core::typed::WireField>::OPTIONAL,
                            ),
                    )
                } else {
                    99.0
                },
                nested: if present.get(__S5) {
                    ::core::option::Option::Some(
                        ::ulog_core::typed::__private::read_array_source(
                            payload,
                            sources,
                            __R5,
                            present
                                .sub(
                                    __S5 + 1,
                                    <Inner as ::ulog_core::typed::WireField>::OPTIONAL,
                                ),
                        ),
                    )
                } else {
                    ::core::option::Option::None
                },
            }
        }
        #[inline]
        fn to_wire(&self) -> [u8; __SIZE] {
            let mut wire = [0u8; __SIZE];
            ::ulog_core::typed::__private::write::<
                u64,
            >(&mut wire, __O0, &self.timestamp);
            if let ::core::option::Option::Some(value) = &self.latitude {
                ::ulog_core::typed::__private::write::<i32>(&mut wire, __O1, value);
            }
            if let ::core::option::Option::Some(value) = &self.latitude_deg {
                ::ulog_core::typed::__private::write::<f64>(&mut wire, __O2, value);
            }
            ::ulog_core::typed::__private::write::<
                u8,
            >(&mut wire, __O3, &self.satellites_used);
            ::ulog_core::typed::__private::write::<f32>(&mut wire, __O4, &self.eph);
            if let ::core::option::Option::Some(value) = &self.nested {
                ::ulog_core::typed::__private::write_array::<
                    Inner,
                >(&mut wire, __O5, value);
            }
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
    impl ::ulog_core::typed::ArrayElement for GpsFix {}
    #[automatically_derived]
    impl ::ulog_core::ULogMessage for GpsFix {
        const NAME: &'static str = "gps_fix";
        const ALIASES: &'static [&'static str] = &[];
        fn schema() -> &'static ::ulog_core::typed::Schema {
            static FIELDS: [::ulog_core::typed::FieldDef; 6usize] = [
                ::ulog_core::typed::FieldDef::new(
                    "timestamp",
                    &[],
                    <u64 as ::ulog_core::typed::WireField>::KIND,
                    <u64 as ::ulog_core::typed::WireField>::COUNT,
                ),
                ::ulog_core::typed::FieldDef::new(
                        "latitude",
                        &["lat"],
                        <i32 as ::ulog_core::typed::WireField>::KIND,
                        <i32 as ::ulog_core::typed::WireField>::COUNT,
                    )
                    .when_absent(::ulog_core::typed::Absent::None),
                ::ulog_core::typed::FieldDef::new(
                        "latitude_deg",
                        &[],
                        <f64 as ::ulog_core::typed::WireField>::KIND,
                        <f64 as ::ulog_core::typed::WireField>::COUNT,
                    )
                    .when_absent(::ulog_core::typed::Absent::None),
                ::ulog_core::typed::FieldDef::new(
                        "satellites_used",
                        &[],
                        <u8 as ::ulog_core::typed::WireField>::KIND,
                        <u8 as ::ulog_core::typed::WireField>::COUNT,
                    )
                    .when_absent(::ulog_core::typed::Absent::Default),
                ::ulog_core::typed::FieldDef::new(
                        "eph",
                        &[],
                        <f32 as ::ulog_core::typed::WireField>::KIND,
                        <f32 as ::ulog_core::typed::WireField>::COUNT,
                    )
                    .when_absent(::ulog_core::typed::Absent::Default),
                ::ulog_core::typed::FieldDef::new(
                        "nested",
                        &[],
                        <Inner as ::ulog_core::typed::WireField>::KIND,
                        ::core::option::Option::Some(2),
                    )
                    .when_absent(::ulog_core::typed::Absent::None),
            ];
            static SCHEMA: ::ulog_core::typed::__private::OnceLock<
                ::ulog_core::typed::Schema,
            > = ::ulog_core::typed::__private::OnceLock::new();
            SCHEMA
                .get_or_init(|| {
                    ::ulog_core::typed::Schema::build("gps_fix", &FIELDS)
                        .with_rust_name("GpsFix", true)
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
                u64,
            >(&self.timestamp, path, base, "timestamp", f);
            if let ::core::option::Option::Some(value) = &self.latitude {
                ::ulog_core::typed::__private::visit_field::<
                    i32,
                >(value, path, base, "latitude", f);
            }
            if let ::core::option::Option::Some(value) = &self.latitude_deg {
                ::ulog_core::typed::__private::visit_field::<
                    f64,
                >(value, path, base, "latitude_deg", f);
            }
            ::ulog_core::typed::__private::visit_field::<
                u8,
            >(&self.satellites_used, path, base, "satellites_used", f);
            ::ulog_core::typed::__private::visit_field::<
                f32,
            >(&self.eph, path, base, "eph", f);
            if let ::core::option::Option::Some(value) = &self.nested {
                ::ulog_core::typed::__private::visit_array::<
                    Inner,
                >(value, path, base, "nested", f);
            }
        }
    }
};
