//! `MakeNamedMedium`, `MediumInterface` and `Attribute "medium"`: lancer has no participating
//! media yet. The reader accepts these directives so that pbrt-v4 scenes with fog or smoke
//! still load, and says once per scene that their media are ignored; nothing here pretends to
//! convert a medium.

/// The one warning a scene with media gets (at its first medium directive).
pub const IGNORED: &str = "participating media are not supported yet; media are ignored";

#[cfg(test)]
mod tests {
    use crate::load_pbrt_str;
    use std::path::Path;

    /// Every medium directive of a scene, and the one warning they give, at the first.
    #[test]
    fn media_are_ignored_with_one_warning_at_the_first() {
        let text = "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1 1 1]\n\
                    WorldBegin\n\
                    Attribute \"medium\" \"float scale\" 2\n\
                    MediumInterface \"fog\" \"\"\n\
                    Shape \"sphere\"\n";
        let loaded = load_pbrt_str(text, "t.pbrt", Path::new(".")).unwrap();
        let warnings: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
        assert_eq!(warnings, [format!("t.pbrt:1:1: {}", super::IGNORED)]);
        assert_eq!(loaded.desc.shapes.len(), 1);
    }
}
