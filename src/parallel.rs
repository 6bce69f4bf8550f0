//! Work split over every core: `f` of each index of a range, in order.

/// `f(0)`, ..., `f(n - 1)` in order, computed on as many scoped threads as the machine offers
/// (each a contiguous chunk of the indices); `Err` with the panic of a worker that panicked.
pub fn map_indices<U: Send>(
    n: usize,
    f: impl Fn(usize) -> U + Sync,
) -> std::thread::Result<Vec<U>> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = n.div_ceil(threads).max(1);
    let f = &f;
    let parts = std::thread::scope(|s| {
        let handles: Vec<_> = (0..n)
            .step_by(chunk)
            .map(|from| s.spawn(move || (from..(from + chunk).min(n)).map(f).collect::<Vec<U>>()))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join())
            .collect::<std::thread::Result<Vec<_>>>()
    })?;
    Ok(parts.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_index_once_in_order() {
        assert_eq!(
            super::map_indices(1001, |i| i * 2).unwrap(),
            (0..1001).map(|i| i * 2).collect::<Vec<_>>()
        );
        assert!(super::map_indices(0, |i| i).unwrap().is_empty());
        // teeth: a worker's panic is an error, not a shorter result
        assert!(super::map_indices(10, |i| if i == 7 { panic!("worker") } else { i }).is_err());
    }
}
