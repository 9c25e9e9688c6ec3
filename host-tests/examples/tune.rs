use rbtrack::fixed::Q16;
use rbtrack::tracker::Variant;
use rbtrack_host::metrics::Evaluation;
use rbtrack_host::run::{track, Options};
use rbtrack_host::scene::{Scene, SceneConfig, Variant as SV};
use rbtrack_host::sequence::{shared_data_dir, Sequence};

fn opts(v: Variant, seed: u64, spr: f64) -> Options {
    let mut o = Options::new(v);
    o.config.seed = seed;
    o.config.scale_per_row = Q16::from_f64(spr);
    o
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let what = args.get(1).map(String::as_str).unwrap_or("scenes");
    if what == "scenes" {
        for sv in SV::ALL {
            for v in [Variant::ColourPf, Variant::Rbpf] {
                let mut mi = 0.0;
                for seed in 1..=5 {
                    let scene = Scene::new(SceneConfig::new(sv, seed)).unwrap();
                    let frames: Vec<Vec<u8>> = scene.frames().collect();
                    let (w, h) = (scene.width() as usize, scene.height() as usize);
                    let truth = scene.boxes();
                    let (boxes, _) = track(&opts(v, seed, scene.scale_per_row()), frames.iter().map(|f| (f.as_slice(), w, h)), &truth[0]).unwrap();
                    let e = Evaluation::new(&truth, &boxes);
                    mi += e.mean_iou / 5.0;
                    print!("{:.2}/{:.2} ", e.mean_iou, e.success_rate);
                }
                println!(" {:?} {:?} mean IoU {:.3}", sv, v, mi);
            }
        }
    } else {
        let data = shared_data_dir().unwrap();
        for v in [Variant::ColourPf, Variant::Rbpf] {
            let mut auc = 0.0;
            for name in ["Crossing", "KiteSurf", "PETS09S2L1_id11", "ball1_vot15", "boat1_uav"] {
                let seq = Sequence::open(data.join(name)).unwrap();
                let frames: Vec<_> = seq.frames().map(|f| f.unwrap()).collect();
                let init = seq.init_box().unwrap();
                let (boxes, steps) = track(&opts(v, 1, 0.0), frames.iter().map(|f| (f.rgb.as_slice(), f.width as usize, f.height as usize)), &init).unwrap();
                let e = Evaluation::new(&seq.groundtruth, &boxes);
                let ms: f64 = steps.iter().map(|s| s.elapsed.as_secs_f64()).sum::<f64>() * 1e3 / steps.len() as f64;
                println!("{name:16} {v:?} auc {:.3} p20 {:.3} miou {:.3} {:.2} ms", e.success_auc, e.precision_20, e.mean_iou, ms);
                auc += e.success_auc / 5.0;
            }
            println!("{v:?} mean auc {auc:.3}");
        }
    }
}
