//! Fallible allocation for everything that grows with the input: a mesh too large for the
//! address space gives [`Error::OutOfMemory`] instead of aborting the host process.

use crate::error::{Error, Result};

/// The error for `count` elements of `T` that could not be allocated.
pub fn out_of_memory<T>(what: &'static str, count: usize) -> Error {
    Error::OutOfMemory { what, bytes: count as u128 * size_of::<T>() as u128 }
}

/// An empty vector with room for `count` elements, or [`Error::OutOfMemory`].
pub fn try_with_capacity<T>(count: usize, what: &'static str) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(count).map_err(|_| out_of_memory::<T>(what, count))?;
    Ok(v)
}

/// A vector of `count` copies of `value`, or [`Error::OutOfMemory`].
pub fn try_filled<T: Clone>(count: usize, value: T, what: &'static str) -> Result<Vec<T>> {
    let mut v = try_with_capacity(count, what)?;
    v.resize(count, value);
    Ok(v)
}

/// A copy of `items`, or [`Error::OutOfMemory`].
pub fn try_copy<T: Clone>(items: &[T], what: &'static str) -> Result<Vec<T>> {
    let mut v = try_with_capacity(items.len(), what)?;
    v.extend_from_slice(items);
    Ok(v)
}

/// Appends `value` to `v`, growing it (geometrically, as `push` does) fallibly.
pub fn try_push<T>(v: &mut Vec<T>, value: T, what: &'static str) -> Result<()> {
    if v.len() == v.capacity() {
        v.try_reserve(1).map_err(|_| out_of_memory::<T>(what, v.len().saturating_mul(2).max(1)))?;
    }
    v.push(value);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_impossible_size_is_an_error_not_an_abort() {
        let e = try_with_capacity::<[f64; 2]>(usize::MAX / 8, "points").unwrap_err();
        assert!(matches!(e, Error::OutOfMemory { what: "points", .. }), "{e}");
        assert!(e.to_string().starts_with("out of memory: cannot allocate"), "{e}");
        assert_eq!(try_filled(3, 7u8, "x").unwrap(), vec![7, 7, 7]);
        assert_eq!(try_copy(&[1, 2], "x").unwrap(), vec![1, 2]);
        let mut v = Vec::new();
        for i in 0..100 {
            try_push(&mut v, i, "x").unwrap();
        }
        assert_eq!(v, (0..100).collect::<Vec<_>>());
    }
}
