//! The block directives of the graphics state: `AttributeBegin`/`End`, `TransformBegin`/`End`,
//! `ObjectBegin`/`End`/`ObjectInstance`, the frame of an `Import`, `WorldBegin`, and
//! `Attribute` defaults.

use super::{Block, Builder, MAX_NESTING};
use crate::error::{Location, SceneError};
use crate::pbrt::params::ParamList;
use crate::pbrt::singular::{is_singular, unplaced};
use lancer::math::Transform;
use lancer::scene::desc::ObjectDesc;

impl Builder {
    /// `Attribute "target" …`: defaults for the parameters of later directives of `target`.
    pub(super) fn attribute(
        &mut self,
        target: String,
        params: ParamList,
        loc: &Location,
    ) -> Result<(), SceneError> {
        if !matches!(
            target.as_str(),
            "shape" | "light" | "material" | "medium" | "texture"
        ) {
            return Err(SceneError::at(
                loc.clone(),
                format!(
                    "Attribute target \"{target}\" is unknown (expected shape, light, \
                     material, medium or texture)"
                ),
            ));
        }
        // A later default replaces an earlier one of the same name, as in pbrt-v4.
        let defaults = self.gs.defaults.entry(target).or_default();
        defaults.retain(|d| !params.has(&d.name));
        defaults.extend(params.iter().cloned());
        Ok(())
    }

    pub(super) fn world_begin(&mut self, loc: &Location) -> Result<(), SceneError> {
        self.require_options("WorldBegin", loc)?;
        if let Some((b, _, open)) = self.stack.last() {
            return Err(SceneError::at(
                loc.clone(),
                format!(
                    "WorldBegin inside the {} at line {}",
                    b.names().0,
                    open.line
                ),
            ));
        }
        self.in_world = true;
        self.gs.ctm = Transform::IDENTITY;
        self.gs.ctm_end = Transform::IDENTITY;
        self.gs.active = super::Active::ALL;
        self.named_coords.insert(
            "world".to_string(),
            (Transform::IDENTITY, Transform::IDENTITY),
        );
        Ok(())
    }

    /// `ObjectBegin`: also begins an attribute block, as in pbrt-v4.
    pub(super) fn object_begin(&mut self, name: String, loc: &Location) -> Result<(), SceneError> {
        self.require_world("ObjectBegin", loc)?;
        if let Some(open) = self.current_object {
            let open = &self.desc.objects[open as usize].name;
            return Err(SceneError::at(
                loc.clone(),
                format!("ObjectBegin \"{name}\" inside the definition of \"{open}\""),
            ));
        }
        self.stack
            .push((Block::Object, self.gs.clone(), loc.clone()));
        let index = self.desc.objects.len() as u32;
        self.desc.objects.push(ObjectDesc {
            name: name.clone(),
            shapes: Vec::new(),
        });
        if self.object_names.insert(name.clone(), index).is_some() {
            self.warn(loc, format!("object \"{name}\" redefined"));
        }
        self.current_object = Some(index);
        Ok(())
    }

    pub(super) fn object_instance(
        &mut self,
        name: String,
        loc: &Location,
    ) -> Result<(), SceneError> {
        self.require_world("ObjectInstance", loc)?;
        if self.current_object.is_some() {
            return Err(SceneError::at(
                loc.clone(),
                "ObjectInstance inside an object definition",
            ));
        }
        if is_singular(&self.gs.ctm) || is_singular(&self.gs.ctm_end) {
            self.warn(loc, unplaced(&format!("ObjectInstance \"{name}\"")));
            return Ok(());
        }
        self.pending_instances
            .push((name, self.animated_ctm(), loc.clone()));
        Ok(())
    }

    /// Saves the graphics state at the opening of a block, refusing nesting deeper than
    /// [`MAX_NESTING`] (each level holds a copy of the state).
    pub(super) fn begin_block(&mut self, block: Block, loc: &Location) -> Result<(), SceneError> {
        if self.stack.len() >= MAX_NESTING {
            let (open, _) = block.names();
            return Err(SceneError::at(
                loc.clone(),
                format!("{open} nested more than {MAX_NESTING} blocks deep"),
            ));
        }
        self.stack.push((block, self.gs.clone(), loc.clone()));
        Ok(())
    }

    pub(super) fn end_block(&mut self, block: Block, loc: &Location) -> Result<(), SceneError> {
        let (begin, end) = block.names();
        match self.stack.pop() {
            None => Err(SceneError::at(
                loc.clone(),
                format!("{end} without a matching {begin}"),
            )),
            Some((b, _, open)) if block == Block::Import && b != block => Err(SceneError::at(
                open,
                format!(
                    "this {} is never closed: the imported file ends first",
                    b.names().0
                ),
            )),
            Some((b, _, open)) if b != block => Err(SceneError::at(
                loc.clone(),
                format!("{end} closes the {} at line {}", b.names().0, open.line),
            )),
            Some((_, saved_gs, _)) => {
                if block == Block::Transform {
                    self.gs.ctm = saved_gs.ctm;
                    self.gs.ctm_end = saved_gs.ctm_end;
                    self.gs.active = saved_gs.active;
                } else {
                    self.gs = saved_gs;
                }
                if block == Block::Object {
                    self.current_object = None;
                }
                Ok(())
            }
        }
    }
}
