//! How many rows a topic will have at the end of a file, judged while reading it, so
//! that vectors filled in one pass grow by one reallocation instead of by doublings
//! that copy them.

/// The rows a topic will likely have once `whole` bytes are read, given `rows` rows
/// in the first `done` bytes: the same rate, with an eighth more as a margin. 0 (no
/// estimate) before the first MiB, or when the length is unknown (`u64::MAX`).
pub(crate) fn rows_at_end(rows: usize, done: u64, whole: u64) -> usize {
    if done < 1 << 20 || whole == u64::MAX {
        return 0;
    }
    let estimate = rows as u128 * u128::from(whole) / u128::from(done);
    usize::try_from(estimate + estimate / 8).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::rows_at_end;

    #[test]
    fn scales_the_rate_so_far_with_a_margin() {
        assert_eq!(rows_at_end(1000, 1 << 20, 4 << 20), 4500);
        assert_eq!(rows_at_end(1000, 1000, 4 << 20), 0);
        assert_eq!(rows_at_end(1000, 1 << 20, u64::MAX), 0);
    }
}
