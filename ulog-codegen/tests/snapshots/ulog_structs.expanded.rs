/// The ULog message `vehicle_attitude`: `vehicle_attitude:uint64_t timestamp;float[4] q;uint8_t type;char[3] name;uint8_t[4] _padding0;`
#[derive(::core::marker::Copy)]
pub struct VehicleAttitude {
    pub timestamp: u64,
    pub q: [f32; 4usize],
    pub r#type: u8,
    pub name: ::ulog_core::typed::CharArray<3usize>,
    pub _padding0: [u8; 4usize],
}
::ulog_core::typed::__private::binding_impls!(VehicleAttitude);
impl ::ulog_core::typed::__private::Binding for VehicleAttitude {
    type Wire = [u8; 32];
    const FORMAT: &'static str = "vehicle_attitude:uint64_t timestamp;float[4] q;uint8_t type;char[3] name;uint8_t[4] _padding0;";
    const SOURCES: usize = 4;
    fn schema() -> &'static ::ulog_core::typed::__private::Schema {
        static SCHEMA: ::ulog_core::typed::__private::SchemaCell = ::ulog_core::typed::__private::SchemaCell::new();
        SCHEMA.get::<Self>()
    }
    fn read(r: &mut ::ulog_core::typed::__private::Reader<'_>) -> Self {
        Self {
            timestamp: r.get(),
            q: r.array(),
            r#type: r.get(),
            name: r.get(),
            _padding0: r.pad(),
        }
    }
    fn write(&self, w: &mut ::ulog_core::typed::__private::Writer<'_>) {
        w.put(&self.timestamp);
        w.array(&self.q);
        w.put(&self.r#type);
        w.put(&self.name);
    }
}
/// The ULog message `pair`: `pair:vehicle_attitude[2] both;`
#[derive(::core::marker::Copy)]
pub struct Pair {
    pub both: [VehicleAttitude; 2usize],
}
::ulog_core::typed::__private::binding_impls!(Pair);
impl ::ulog_core::typed::__private::Binding for Pair {
    type Wire = [u8; 64];
    const FORMAT: &'static str = "pair:vehicle_attitude[2] both;";
    const NESTED: &'static [fn() -> &'static ::ulog_core::typed::__private::Schema] = &[
        <VehicleAttitude as ::ulog_core::typed::__private::Binding>::schema,
    ];
    const SOURCES: usize = 8;
    fn schema() -> &'static ::ulog_core::typed::__private::Schema {
        static SCHEMA: ::ulog_core::typed::__private::SchemaCell = ::ulog_core::typed::__private::SchemaCell::new();
        SCHEMA.get::<Self>()
    }
    fn read(r: &mut ::ulog_core::typed::__private::Reader<'_>) -> Self {
        Self { both: r.array() }
    }
    fn write(&self, w: &mut ::ulog_core::typed::__private::Writer<'_>) {
        w.array(&self.both);
    }
}
