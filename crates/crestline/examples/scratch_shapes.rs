use crestline::io::{Format, WriteOptions, write_mesh};
use crestline::shapes;
fn main() {
    let out = std::path::Path::new("/tmp/sal");
    let w = |name: &str, m: &crestline::TriMesh| {
        write_mesh(&out.join(name), m, Format::Obj, &WriteOptions::DEFAULT).unwrap()
    };
    w("sphere3.obj", &shapes::icosphere(2.0, 3));
    w("sphere5.obj", &shapes::icosphere(2.0, 5));
    w("torus.obj", &shapes::torus(3.0, 1.0, 120, 40));
    w("torus_fine.obj", &shapes::torus(3.0, 1.0, 240, 80));
    w("pillow.obj", &shapes::pillow_box(1.0, 0.25, 40).0);
}
