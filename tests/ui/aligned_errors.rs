use ulog_core::align::Aligned;
use ulog_core::ULogMessage;

#[derive(ULogMessage)]
struct Good {
    timestamp: u64,
}

#[derive(Aligned)]
struct Every {
    plain: Good,
    #[ulog(method = "cubic")]
    cubic: Option<Good>,
    #[ulog(instance = 300)]
    many: Option<Good>,
    #[ulog(instance = 1, instance = 2)]
    twice: Option<Good>,
    #[ulog(rate = 10)]
    unknown: Option<Good>,
}

#[derive(Aligned)]
struct Tuple(Option<Good>);

#[derive(Aligned)]
enum NotAStruct {
    A,
}

#[derive(Aligned)]
struct Generic<T> {
    t: Option<T>,
}

fn main() {}
