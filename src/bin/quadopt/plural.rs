//! Counts in the reports, in the singular for one: "1 quad", "2 quads".

/// `n` followed by `one` when `n` is 1, else by `many`.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

#[cfg(test)]
mod tests {
    #[test]
    fn one_is_singular_and_every_other_count_plural() {
        assert_eq!(super::count(1, "vertex", "vertices"), "1 vertex");
        assert_eq!(super::count(0, "quad", "quads"), "0 quads");
        assert_eq!(super::count(2, "iteration", "iterations"), "2 iterations");
    }
}
