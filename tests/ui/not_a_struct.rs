use ulog_core::{ULogMessage, ULogTopics};

#[derive(ULogMessage)]
struct Tuple(u8, u16);

#[derive(ULogMessage)]
struct Generic<T> {
    x: T,
}

#[derive(ULogMessage)]
enum E {
    A,
}

#[derive(ULogMessage)]
struct Good {
    x: u8,
}

#[derive(ULogTopics)]
enum Topics {
    A(Good),
    B { x: Good },
    C(Good),
}

fn main() {}
