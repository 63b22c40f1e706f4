//! Counts in the reports, in the singular for one: "1 quad", "2 quads".

/// `n` followed by `one` when `n` is 1, else by `many`.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The faces of a mesh: "5 quads" for a pure quad mesh (as before triangles were read), else
/// "7 faces (5 quads, 2 triangles)".
pub fn faces(quads: usize, triangles: usize) -> String {
    if triangles == 0 {
        return count(quads, "quad", "quads");
    }
    format!(
        "{} ({}, {})",
        count(quads + triangles, "face", "faces"),
        count(quads, "quad", "quads"),
        count(triangles, "triangle", "triangles")
    )
}

/// "quad" and "quads" for a pure quad mesh, else "face" and "faces".
pub fn face_words(triangles: bool) -> (&'static str, &'static str) {
    if triangles { ("face", "faces") } else { ("quad", "quads") }
}

#[cfg(test)]
mod tests {
    #[test]
    fn one_is_singular_and_every_other_count_plural() {
        assert_eq!(super::count(1, "vertex", "vertices"), "1 vertex");
        assert_eq!(super::count(0, "quad", "quads"), "0 quads");
        assert_eq!(super::count(2, "iteration", "iterations"), "2 iterations");
    }

    #[test]
    fn faces_say_quads_for_a_quad_mesh_and_name_both_kinds_otherwise() {
        assert_eq!(super::faces(5, 0), "5 quads");
        assert_eq!(super::faces(1, 0), "1 quad");
        assert_eq!(super::faces(5, 2), "7 faces (5 quads, 2 triangles)");
        assert_eq!(super::faces(0, 1), "1 face (0 quads, 1 triangle)");
    }
}
