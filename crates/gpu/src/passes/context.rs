//! What every pass records against: one frame's context. It names only resources (the
//! prepared scene, the targets, the groups over them), never another pass.

use crate::resources::PreparedScene;
use crate::resources::conditional::ConditionalBuffers;
use crate::resources::groups::TargetGroups;
use crate::resources::lights::VolumeDraw;
use crate::resources::targets::Targets;

/// What a pass records against: the scene's resources, the targets and the renderer's
/// groups.
pub(crate) struct FrameContext<'a> {
    pub scene: &'a PreparedScene,
    pub targets: &'a Targets,
    pub groups: &'a TargetGroups,
    /// Whether this frame's static query placed instances (the static draw lists are
    /// drawn only then: without a query this frame, they hold an older frame's draws).
    pub static_query: bool,
    /// This frame's stencil light volumes (empty: lighting reads no accumulation).
    pub volumes: &'a [VolumeDraw],
    /// The shadow views' caster culling (empty lists: every caster).
    pub casters: &'a crate::shadows::CasterCulls,
    /// Per sun slice: whether the static query's shadow view of the slice placed its
    /// static casters this frame (into the scene's `static_shadows` set of the slice);
    /// the slice draws those instead of the camera query's lists.
    pub static_slices: &'a [bool],
    /// KZ2's conditional rendering emulated: this frame's plan and buffers (`None`: off).
    pub conditional: Option<&'a ConditionalBuffers>,
    /// Scene origin minus camera position (origin-relative to camera-relative), metres.
    pub origin_offset: glam::Vec3,
    /// The baseline's MSAA frame: its depth prepass, G-buffer pass, light tiles and
    /// lighting use the multisampled targets (`targets.msaa`).
    pub msaa: bool,
    /// This frame's laydown is the compute one (set with [`Laydown::Compute`](crate::Laydown)
    /// where the device and the scene have its resources, in frames without a static
    /// query, whose indirect draw lists only the hardware laydown draws).
    pub compute_laydown: bool,
    /// FC5's water's HDR colour group, when the renderer has a water scene and the frame
    /// lights (lighting keeps its HDR colour there; the water passes run after it).
    pub water_hdr: Option<&'a wgpu::BindGroup>,
}
