//! The library version: the `QUADOPT_VERSION_*` constants and the functions that return it.

use std::ffi::{CStr, c_char};

use super::boundary::boundary_or;

/// Major version of the library (the `x` of `x.y.z`).
pub const QUADOPT_VERSION_MAJOR: u32 = 0;
/// Minor version of the library (the `y` of `x.y.z`).
pub const QUADOPT_VERSION_MINOR: u32 = 1;
/// Patch version of the library (the `z` of `x.y.z`).
pub const QUADOPT_VERSION_PATCH: u32 = 0;

/// The library version as a static string, e.g. "0.1.0". Never NULL.
#[unsafe(no_mangle)]
pub extern "C" fn quadopt_version() -> *const c_char {
    const VERSION: &CStr =
        match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
            Ok(v) => v,
            Err(_) => panic!("the package version contains a NUL"),
        };
    VERSION.as_ptr()
}

/// The library version as numbers, written to each non-NULL argument.
///
/// # Safety
/// Each argument must be NULL or point to a writable, aligned `uint32_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn quadopt_version_numbers(major: *mut u32, minor: *mut u32, patch: *mut u32) {
    boundary_or((), || {
        for (ptr, value) in
            [(major, QUADOPT_VERSION_MAJOR), (minor, QUADOPT_VERSION_MINOR), (patch, QUADOPT_VERSION_PATCH)]
        {
            if !ptr.is_null() && ptr.is_aligned() {
                // SAFETY: non-null and aligned; writable by the contract.
                unsafe { ptr.write(value) };
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ptr::null_mut;

    #[test]
    fn version() {
        // SAFETY: static string.
        let v = unsafe { CStr::from_ptr(quadopt_version()) }.to_str().unwrap();
        assert_eq!(v, env!("CARGO_PKG_VERSION"));
        let (mut a, mut b, mut c) = (9, 9, 9);
        // SAFETY: writable u32s or NULL.
        unsafe {
            quadopt_version_numbers(&mut a, &mut b, &mut c);
            quadopt_version_numbers(null_mut(), null_mut(), null_mut());
        }
        assert_eq!(format!("{a}.{b}.{c}"), v);
        assert_eq!(
            (QUADOPT_VERSION_MAJOR, QUADOPT_VERSION_MINOR, QUADOPT_VERSION_PATCH),
            (a, b, c),
            "update the QUADOPT_VERSION_* constants with Cargo.toml's version"
        );
    }
}
