//! The parallel query equals the sequential one exactly: instances, batches, stats and the
//! fade states they leave, frame after frame.

mod common;

use common::*;
use glam::{DQuat, DVec3, Mat4};
use staticscene::demo::box_hiz;
use staticscene::{
    Camera, DrawableSetupInstance, QueryOptions, QueryOutput, QueryParams, ViewDesc, WaveWidth,
};

#[test]
fn par_query_equals_query() {
    let (mut a, cfg) = city_scene(80_000, 11);
    let (mut b, _) = city_scene(80_000, 11);
    let c = staticscene::demo::city(&cfg);
    let size = cfg.lots[0] as f64 * f64::from(cfg.lot_size);
    let (w, h) = (320, 180);
    for frame in 0..12 {
        let t = frame as f64 / 12.0;
        let cam = Camera {
            position: DVec3::new(size * (0.2 + 0.6 * t), 1.7 + 30.0 * t, size * 0.5),
            rotation: DQuat::from_rotation_y(t * 3.0),
            projection: Mat4::perspective_rh(1.2, 16.0 / 9.0, 0.1, 5000.0),
            reversed_depth: false,
        };
        let hiz = box_hiz(&c.building_boxes, &cam, &cam, w, h, false).unwrap();
        let mut view = ViewDesc::camera(cam, [w, h]);
        view.fade_frames = 6;
        view.occlusion_camera = Some(cam);
        let params = QueryParams::new(&view).unwrap();
        for precull in [true, false] {
            let options = QueryOptions {
                wave_width: if frame % 2 == 0 {
                    WaveWidth::W64
                } else {
                    WaveWidth::W32
                },
                precull,
            };
            let (mut sa, mut sb) = (
                QueryOutput::<DrawableSetupInstance>::new(),
                QueryOutput::new(),
            );
            a.query(&params, Some(&hiz), &options, &mut sa).unwrap();
            b.par_query(&params, Some(&hiz), &options, &mut sb).unwrap();
            assert_eq!(sa.stats, sb.stats, "frame {frame}");
            assert!(
                sa.instances == sb.instances,
                "frame {frame}: instances differ"
            );
            assert!(sa.batches == sb.batches, "frame {frame}: batches differ");
            if frame > 3 {
                assert!(!sa.instances.is_empty());
            }
        }
    }
    for (ta, tb) in a.tiles().iter().zip(b.tiles()) {
        assert_eq!(ta.id(), tb.id());
        for i in 0..ta.instances().len() {
            assert_eq!(a.fade_state(ta.id(), i), b.fade_state(tb.id(), i));
        }
    }
}
