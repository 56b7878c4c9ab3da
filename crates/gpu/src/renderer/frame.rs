//! A frame's uploads: its constants, the sun's bake and cascades, the lights, the water's
//! constants and KZ2's conditional plan, all through the frame's upload pool.

use super::*;

impl Renderer {
    /// Uploads the frame constants of `frame` for `scene`, and its point lights when they
    /// differ from the last upload.
    pub(super) fn upload_frame(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
        statics: Option<&mut StaticView<'_>>,
    ) -> Result<()> {
        let static_frame = statics.is_some();
        frame.validate()?;
        self.check_scene(scene)?;
        let previous = self
            .previous
            .filter(|(id, _)| *id == scene.id)
            .map(|(_, p)| p);
        let origin = scene.summary.origin;
        let mut uniforms = frame_uniforms(
            frame,
            scene.wind.as_ref(),
            origin,
            (self.config.image.width, self.config.image.height),
            self.config.image.mip_bias,
            self.frame_index,
            previous,
        );
        uniforms.vrs = self.config.geometry.vrs.map_or([0.0; 4], |v| v.uniform());
        self.bake_sun(scene, frame, &mut uniforms, statics)?;
        uniforms.local_light_count = self.upload_lights(frame, &uniforms)?;
        // Swaying foliage moves its shadows: a cached slice is stale once time moved.
        let animated = scene.wind.is_some() && uniforms.prev_time != uniforms.time;
        self.upload_shadows(scene.id, static_frame || animated, frame, &uniforms)?;
        self.uploads
            .write(&self.frame, 0, bytemuck::bytes_of(&uniforms));
        if let Some(w) = &self.water {
            let aspect = self.config.image.width as f32 / self.config.image.height as f32;
            let u = w.data.frame_constants(frame, aspect);
            self.uploads.write(&w.data.frame, 0, bytemuck::bytes_of(&u));
            if !w.data.decals_cpu.is_empty() {
                self.uploads
                    .write(&w.data.decals, 0, bytemuck::cast_slice(&w.data.decals_cpu));
            }
        }
        self.view_rotation = frame.camera.view_rotation();
        self.origin_offset = glam::Vec4::from(uniforms.origin_offset).truncate();
        self.plan_conditional(scene)?;
        let aspect = self.config.image.width as f32 / self.config.image.height as f32;
        self.previous = Some((
            scene.id,
            PreviousCamera {
                view_proj: frame.camera.relative_view_projection(aspect),
                position: frame.camera.position,
                time: frame.time,
            },
        ));
        self.frame_index = self.frame_index.wrapping_add(1);
        Ok(())
    }
}
