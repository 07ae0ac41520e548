//! What the reader gives: a scene description with its warnings and notes.

use crate::error::Warning;
use lancer::scene::desc::SceneDesc;

/// A scene read: its description, its warnings, and its notes (what the reader made, such as
/// the displaced meshes' triangle counts).
pub struct Built {
    /// The scene.
    pub desc: SceneDesc,
    /// What lancer does differently, or what is wrong but readable.
    pub warnings: Vec<Warning>,
    /// Facts worth printing.
    pub notes: Vec<Warning>,
}
