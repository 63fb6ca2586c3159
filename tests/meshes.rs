//! Bounding volumes from mesh files the tests write themselves: a box, a
//! cylinder (a prism of many sides) and a tetrahedron as STL (ASCII and
//! binary), OBJ and COLLADA. The checker's ellipsoid of each equals the
//! analytic minimum-volume enclosing ellipsoid; scale, origin, COLLADA's
//! unit, `package://` paths and missing or hostile meshes are handled.

use momentlmi::moments::urdf_check::check_urdf_file;
use momentlmi::urdf::mesh::{MeshPaths, read_vertices};
use std::path::{Path, PathBuf};

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("momentlmi-mesh-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The 8 corners and 12 triangles of a box of sides `s` centred at 0.
fn box_mesh(s: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let v = (0..8)
        .map(|k| {
            std::array::from_fn(|i| {
                if k >> i & 1 == 1 {
                    0.5 * s[i]
                } else {
                    -0.5 * s[i]
                }
            })
        })
        .collect();
    let f = vec![
        [0, 1, 3],
        [0, 3, 2],
        [4, 6, 7],
        [4, 7, 5],
        [0, 4, 5],
        [0, 5, 1],
        [2, 3, 7],
        [2, 7, 6],
        [0, 2, 6],
        [0, 6, 4],
        [1, 5, 7],
        [1, 7, 3],
    ];
    (v, f)
}

/// A regular tetrahedron inscribed in the sphere of radius `r` at 0.
fn tetra(r: f64) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let k = r / 3f64.sqrt();
    let v = vec![[k, k, k], [k, -k, -k], [-k, k, -k], [-k, -k, k]];
    (v, vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
}

/// A prism of `n` sides approximating a cylinder of radius r, length l, z axis.
fn prism(r: f64, l: f64, n: usize) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let mut v = vec![];
    for z in [-0.5 * l, 0.5 * l] {
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            v.push([r * a.cos(), r * a.sin(), z]);
        }
    }
    let f = (0..n)
        .flat_map(|k| {
            let j = (k + 1) % n;
            [[k, j, n + j], [k, n + j, n + k]]
        })
        .collect();
    (v, f)
}

fn stl_ascii(v: &[[f64; 3]], f: &[[usize; 3]]) -> String {
    let mut s = String::from("solid t\n");
    for t in f {
        s += "facet normal 0 0 0\nouter loop\n";
        for &i in t {
            s += &format!("vertex {} {} {}\n", v[i][0], v[i][1], v[i][2]);
        }
        s += "endloop\nendfacet\n";
    }
    s + "endsolid t\n"
}

fn stl_binary(v: &[[f64; 3]], f: &[[usize; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend((f.len() as u32).to_le_bytes());
    for t in f {
        b.extend([0u8; 12]);
        for &i in t {
            for x in v[i] {
                b.extend((x as f32).to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

fn obj(v: &[[f64; 3]], f: &[[usize; 3]]) -> String {
    let mut s = String::from("mtllib never_read.mtl\n");
    for p in v {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in f {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

/// COLLADA with `unit` metres per file unit (coordinates divided by it).
fn dae(v: &[[f64; 3]], f: &[[usize; 3]], unit: f64) -> String {
    let pos: Vec<String> = v
        .iter()
        .flat_map(|p| p.iter().map(move |x| format!("{}", x / unit)))
        .collect();
    let idx: Vec<String> = f
        .iter()
        .flat_map(|t| t.iter().map(|i| i.to_string()))
        .collect();
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="u" meter="{unit}"/><up_axis>Z_UP</up_axis></asset>
<library_geometries><geometry id="g" name="g"><mesh>
<source id="p"><float_array id="pa" count="{n}">{pos}</float_array>
<technique_common><accessor source="#pa" count="{nv}" stride="3">
<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
</accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="{nf}"><input semantic="VERTEX" source="#v" offset="0"/><p>{idx}</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node>
</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##,
        n = pos.len(),
        pos = pos.join(" "),
        nv = v.len(),
        nf = f.len(),
        idx = idx.join(" ")
    )
}

/// A URDF with one link whose collision is `mesh` (with `scale` and
/// `origin`) and the given inertial.
fn urdf(mesh: &str, scale: &str, origin: &str, inertial: &str) -> String {
    format!(
        r#"<robot name="m"><link name="base"/>
<link name="body"><inertial>{inertial}</inertial>
<collision><origin xyz="{origin}"/><geometry><mesh filename="{mesh}" scale="{scale}"/></geometry></collision></link>
<joint name="j" type="revolute"><parent link="base"/><child link="body"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#
    )
}

/// A solid box's inertial (sides s, mass m) centred at `at`.
fn solid_box(m: f64, s: [f64; 3], at: [f64; 3]) -> String {
    let i = |a: f64, b: f64| m / 12.0 * (a * a + b * b);
    format!(
        r#"<origin xyz="{} {} {}"/><mass value="{m}"/><inertia ixx="{}" ixy="0" ixz="0" iyy="{}" iyz="0" izz="{}"/>"#,
        at[0],
        at[1],
        at[2],
        i(s[1], s[2]),
        i(s[0], s[2]),
        i(s[0], s[1])
    )
}

fn semi_axes(path: &Path) -> [f64; 3] {
    let v: Vec<nalgebra::Vector3<f64>> = read_vertices(path)
        .unwrap()
        .into_iter()
        .map(nalgebra::Vector3::from)
        .collect();
    let e = momentlmi::moments::Ellipsoid::minimum_volume_enclosing(&v, 1e-9).unwrap();
    let mut s: [f64; 3] = e.semi_axes.into();
    s.sort_by(f64::total_cmp);
    s
}

#[test]
fn the_mvee_of_each_format_is_the_analytic_one() {
    let d = dir("formats");
    let sides = [0.4, 0.2, 0.1];
    let (bv, bf) = box_mesh(sides);
    // a box's MVEE: semi-axes √3 · half sides
    let want_box = [0.05, 0.1, 0.2].map(|h: f64| h * 3f64.sqrt());
    let files = [
        ("box_ascii.stl", stl_ascii(&bv, &bf).into_bytes()),
        ("box_binary.stl", stl_binary(&bv, &bf)),
        ("box.obj", obj(&bv, &bf).into_bytes()),
        ("box_mm.dae", dae(&bv, &bf, 0.001).into_bytes()),
    ];
    for (name, bytes) in files {
        let p = d.join(name);
        std::fs::write(&p, bytes).unwrap();
        let got = semi_axes(&p);
        for (g, w) in got.iter().zip(want_box) {
            assert!((g - w).abs() < 1e-4 * w, "{name}: {got:?} vs {want_box:?}");
        }
    }
    // a regular tetrahedron's MVEE is its circumscribed sphere
    let (tv, tf) = tetra(0.3);
    let p = d.join("tetra.stl");
    std::fs::write(&p, stl_binary(&tv, &tf)).unwrap();
    for g in semi_axes(&p) {
        assert!((g - 0.3).abs() < 1e-4, "tetrahedron {g}");
    }
    // a 64-sided prism: the MVEE of its 128 corners is the cylinder's
    // enclosing ellipsoid, semi-axes √(3/2) r and √3 l/2
    let (pv, pf) = prism(0.1, 0.5, 64);
    let p = d.join("cyl.obj");
    std::fs::write(&p, obj(&pv, &pf)).unwrap();
    let got = semi_axes(&p);
    let want = [0.1 * 1.5f64.sqrt(), 0.1 * 1.5f64.sqrt(), 0.25 * 3f64.sqrt()];
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 2e-3 * w, "prism {got:?} vs {want:?}");
    }
}

#[test]
fn the_checker_bounds_mesh_links_with_scale_and_origin() {
    let d = dir("check");
    let (bv, bf) = box_mesh([1.0, 1.0, 1.0]);
    std::fs::write(d.join("unit_box.stl"), stl_ascii(&bv, &bf)).unwrap();
    // scale (0.4, 0.2, 0.1) and origin (0.3, 0, 0): the box of those sides
    // there; its own solid inertia is realizable, a point far off is not
    let at = [0.3, 0.0, 0.0];
    let inside = solid_box(2.0, [0.4, 0.2, 0.1], at);
    let outside = solid_box(2.0, [0.4, 0.2, 0.1], [1.0, 0.0, 0.0]);
    for (inertial, want) in [(inside, true), (outside, false)] {
        let u = d.join("m.urdf");
        std::fs::write(
            &u,
            urdf("unit_box.stl", "0.4 0.2 0.1", "0.3 0 0", &inertial),
        )
        .unwrap();
        let (_, rep) = check_urdf_file(&u, &[]).unwrap();
        let l = rep.links.iter().find(|l| l.name == "body").unwrap();
        assert_eq!(l.geometry_primitives, 1, "{:?}", l.geometry_notes);
        assert_eq!(
            l.realizable_in_geometry,
            Some(want),
            "{:?}",
            l.geometry_notes
        );
        assert!(rep.warnings.is_empty(), "{:?}", rep.warnings);
    }
    // without the scale, the same inertia is realizable in the unit box's
    // ellipsoid too; with a tiny scale it is not
    let u = d.join("s.urdf");
    let tight = solid_box(2.0, [0.4, 0.2, 0.1], [0.0, 0.0, 0.0]);
    std::fs::write(&u, urdf("unit_box.stl", "0.01 0.01 0.01", "0 0 0", &tight)).unwrap();
    let (_, rep) = check_urdf_file(&u, &[]).unwrap();
    assert_eq!(rep.links[0].realizable_in_geometry, Some(false));
}

#[test]
fn package_paths_are_searched_and_a_missing_mesh_is_a_warning() {
    let d = dir("package");
    let pkg = d.join("share").join("my_robot").join("meshes");
    std::fs::create_dir_all(&pkg).unwrap();
    let (bv, bf) = box_mesh([0.4, 0.2, 0.1]);
    std::fs::write(pkg.join("b.stl"), stl_binary(&bv, &bf)).unwrap();
    let urdf_dir = d.join("elsewhere");
    std::fs::create_dir_all(&urdf_dir).unwrap();
    let u = urdf_dir.join("r.urdf");
    let inertial = solid_box(1.0, [0.4, 0.2, 0.1], [0.0, 0.0, 0.0]);
    std::fs::write(
        &u,
        urdf(
            "package://my_robot/meshes/b.stl",
            "1 1 1",
            "0 0 0",
            &inertial,
        ),
    )
    .unwrap();
    // not found: a warning naming the link and the path, the check goes on
    let (_, rep) = check_urdf_file(&u, &[]).unwrap();
    assert_eq!(rep.links[0].realizable_in_geometry, None);
    assert!(
        rep.warnings
            .iter()
            .any(|w| w.to_string().contains("link 'body'")
                && w.to_string().contains("package://my_robot")),
        "{:?}",
        rep.warnings
    );
    // a folder of packages, or the package folder itself
    for p in [d.join("share"), d.join("share").join("my_robot")] {
        let (_, rep) = check_urdf_file(&u, &[p]).unwrap();
        assert_eq!(
            rep.links[0].realizable_in_geometry,
            Some(true),
            "{:?}",
            rep.warnings
        );
    }
    // resolution by itself
    let paths = MeshPaths {
        urdf_dir: urdf_dir.clone(),
        package_paths: vec![d.join("share")],
        ros_package_path: false,
    };
    assert_eq!(
        paths.resolve("package://my_robot/meshes/b.stl").unwrap(),
        pkg.join("b.stl")
    );
    assert!(paths.resolve("package://other/b.stl").is_err());
}

#[test]
fn hostile_meshes_are_warnings_not_failures() {
    let d = dir("hostile");
    let bomb = r#"<?xml version="1.0"?><!DOCTYPE c [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;">]><COLLADA>&b;</COLLADA>"#;
    let cases: [(&str, &[u8]); 5] = [
        ("bomb.dae", bomb.as_bytes()),
        ("empty.stl", b""),
        ("garbage.stl", &[0xff; 200]),
        ("flat.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\n"),
        ("x.ply", b"ply\n"),
    ];
    let inertial = solid_box(1.0, [0.1, 0.1, 0.1], [0.0, 0.0, 0.0]);
    for (name, bytes) in cases {
        std::fs::write(d.join(name), bytes).unwrap();
        let u = d.join("h.urdf");
        std::fs::write(&u, urdf(name, "1 1 1", "0 0 0", &inertial)).unwrap();
        let (_, rep) = check_urdf_file(&u, &[]).unwrap();
        assert_eq!(rep.links[0].realizable_in_geometry, None, "{name}");
        assert!(
            rep.warnings
                .iter()
                .any(|w| w.to_string().contains("link 'body'")),
            "{name}: {:?}",
            rep.warnings
        );
    }
}

/// One ellipsoid enclosing several: every point of every part is inside.
#[test]
fn the_enclosing_ellipsoid_contains_every_part() {
    use momentlmi::moments::Ellipsoid;
    use nalgebra::Vector3;
    let a = Ellipsoid::new(Vector3::new(0.1, 0.0, 0.0), Vector3::new(0.2, 0.05, 0.05)).unwrap();
    let b = Ellipsoid::new(Vector3::new(0.0, 0.0, 0.3), Vector3::new(0.04, 0.04, 0.15)).unwrap();
    let e = Ellipsoid::enclosing(&[a, b]).unwrap();
    for part in [a, b] {
        for k in 0..2000 {
            // dense directions, not the ones the construction uses
            let z = -1.0 + 2.0 * (k as f64 + 0.25) / 2000.0;
            let t = 2.399963 * k as f64 * 1.7;
            let r = (1.0 - z * z).sqrt();
            let u = Vector3::new(r * t.cos(), r * t.sin(), z);
            let x = part.center + part.rotation * part.semi_axes.component_mul(&u);
            assert!(e.contains(&x, 1e-9), "{x:?} outside");
        }
    }
    // and it is not wildly larger than the two parts' hull needs
    assert!(e.volume() < 10.0 * (a.volume() + b.volume()));
}

/// A URDF robot whose links have primitive collision shapes (one link has
/// two) identifies at the ellipsoid level: each link body gets one bounding
/// ellipsoid from its geometry, and every identified link is density
/// realizable in it.
#[test]
fn a_urdf_robot_identifies_at_the_ellipsoid_level_from_its_geometry() {
    use momentlmi::dynamics::robots::load_robot;
    use momentlmi::effects::simulate;
    use momentlmi::identify::{Identification, Level};
    use momentlmi::sim::{Effects, SimConfig};
    let d = dir("identify");
    let u = d.join("arm.urdf");
    std::fs::write(
        &u,
        r#"<robot name="arm"><link name="base"/>
<link name="upper"><inertial><origin xyz="0.15 0 0"/><mass value="1.2"/>
<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
<collision><origin xyz="0.15 0 0"/><geometry><box size="0.34 0.06 0.06"/></geometry></collision></link>
<link name="fore"><inertial><origin xyz="0.12 0 0"/><mass value="0.6"/>
<inertia ixx="0.0004" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.004"/></inertial>
<collision><origin xyz="0.1 0 0" rpy="0 1.5707963 0"/><geometry><cylinder radius="0.03" length="0.22"/></geometry></collision>
<collision><origin xyz="0.23 0 0"/><geometry><sphere radius="0.04"/></geometry></collision></link>
<joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 1 0"/>
<limit lower="-2" upper="2" effort="20" velocity="5"/></joint>
<joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.3 0 0"/>
<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="20" velocity="5"/></joint></robot>"#,
    )
    .unwrap();
    let robot = load_robot(u.to_str().unwrap(), None).unwrap();
    assert!(
        robot.bounding().iter().all(|b| b.len() == 1),
        "{:?}",
        robot.warnings
    );
    let cfg = SimConfig::for_robot(&robot, 4.0, Effects::default(), 3);
    let data = simulate(&robot, &cfg, |_, _| {}).unwrap();
    let r = Identification::for_robot(&robot, Level::Ellipsoid, 1e-6)
        .unwrap()
        .identify(&data, None)
        .unwrap();
    assert!(r.constraints_satisfied);
    for name in ["upper", "fore"] {
        let b = r.body(name).unwrap();
        assert!(b.realizability.as_ref().unwrap().realizable, "{name}");
    }
}

/// Bounding volumes cost nothing unused: loading a URDF robot and
/// identifying it at the consistent level reads no mesh; the ellipsoid level
/// (or a later per-body ellipsoid level) computes them then.
#[test]
fn bounding_volumes_are_computed_only_when_a_level_needs_them() {
    use momentlmi::dynamics::robots::load_robot;
    use momentlmi::effects::simulate;
    use momentlmi::identify::{Identification, Level};
    use momentlmi::sim::{Effects, SimConfig};
    let d = dir("lazy");
    let (v, f) = box_mesh([0.3, 0.06, 0.06]);
    std::fs::write(d.join("upper.stl"), stl_ascii(&v, &f)).unwrap();
    let u = d.join("arm.urdf");
    std::fs::write(&u, two_link_arm(r#"<mesh filename="upper.stl"/>"#, "")).unwrap();
    let robot = load_robot(u.to_str().unwrap(), None).unwrap();
    assert!(!robot.bounds.is_resolved(), "computed at load");
    let data = simulate(
        &robot,
        &SimConfig::for_robot(&robot, 2.0, Effects::default(), 3),
        |_, _| {},
    )
    .unwrap();
    let r = Identification::for_robot(&robot, Level::Consistent, 1e-6).unwrap();
    r.identify(&data, None).unwrap();
    assert!(
        !robot.bounds.is_resolved(),
        "computed for the consistent level"
    );
    let id = Identification::for_robot(&robot, Level::Consistent, 1e-6)
        .unwrap()
        .level("upper", Level::Ellipsoid)
        .unwrap();
    assert!(
        robot.bounds.is_resolved(),
        "not computed for the ellipsoid level"
    );
    let r = id.identify(&data, None).unwrap();
    let upper = r.body("upper").unwrap();
    assert!(upper.realizability.as_ref().unwrap().realizable);
    // the mesh's box: semi-axes √3 × the half-sides (the mesh's closed form)
    let e = robot.bounding()[0][0];
    let mut a: Vec<f64> = e.semi_axes.iter().copied().collect();
    a.sort_by(f64::total_cmp);
    for (x, h) in a.iter().zip([0.03, 0.03, 0.15]) {
        assert!((x - 3f64.sqrt() * h).abs() < 1e-6, "{a:?}");
    }
}

/// A collision mesh that is missing falls back to the link's visual
/// geometry, with a warning naming both; with no visual geometry the other
/// collision shapes bound the link alone; with none at all, the ellipsoid
/// level names the link's body.
#[test]
fn a_missing_collision_mesh_falls_back_to_the_visual_geometry() {
    use momentlmi::dynamics::robots::load_robot;
    let d = dir("fallback");
    let (v, f) = box_mesh([0.3, 0.06, 0.06]);
    std::fs::write(d.join("upper_visual.stl"), stl_ascii(&v, &f)).unwrap();
    let visual = r#"<visual><geometry><mesh filename="upper_visual.stl"/></geometry></visual>"#;
    let load = |name: &str, text: String| {
        let u = d.join(name);
        std::fs::write(&u, text).unwrap();
        load_robot(u.to_str().unwrap(), None).unwrap()
    };
    // visual fallback
    let r = load(
        "a.urdf",
        two_link_arm(r#"<mesh filename="gone.stl"/>"#, visual),
    );
    let b = r.bounding()[0].clone();
    assert_eq!(b.len(), 1);
    let mut a: Vec<f64> = b[0].semi_axes.iter().copied().collect();
    a.sort_by(f64::total_cmp);
    assert!(
        (a[2] - 3f64.sqrt() * 0.15).abs() < 1e-6,
        "the visual box bounds it: {a:?}"
    );
    let w: Vec<String> = r
        .bounding_warnings()
        .iter()
        .map(|w| w.to_string())
        .collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("gone.stl") && w[0].contains("upper_visual.stl"),
        "{w:?}"
    );
    assert!(
        w[0].contains("link 'upper'") && w[0].contains("visual geometry"),
        "{w:?}"
    );
    // other collision shapes alone
    let extra = r#"<collision><geometry><sphere radius="0.05"/></geometry></collision>"#;
    let r = load(
        "b.urdf",
        two_link_arm(r#"<mesh filename="gone.stl"/>"#, extra),
    );
    assert!((r.bounding()[0][0].semi_axes.max() - 0.05).abs() < 1e-5);
    let w = r.bounding_warnings()[0].to_string();
    assert!(
        w.contains("other collision shapes bound the link alone"),
        "{w}"
    );
    // nothing: the ellipsoid level names the body
    let r = load("c.urdf", two_link_arm(r#"<mesh filename="gone.stl"/>"#, ""));
    assert!(r.bounding()[0].is_empty());
    let e = r.single_ellipsoids().unwrap_err().to_string();
    assert!(e.contains("body 'upper' has no bounding ellipsoid"), "{e}");
}

/// A two-link arm whose link `upper` has one collision shape `geometry`
/// and the extra elements `extra` (visuals, more collisions); `fore` a box.
fn two_link_arm(geometry: &str, extra: &str) -> String {
    format!(
        r#"<robot name="arm"><link name="base"/>
<link name="upper"><inertial><origin xyz="0 0 0"/><mass value="1.2"/>
<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
<collision><geometry>{geometry}</geometry></collision>{extra}</link>
<link name="fore"><inertial><origin xyz="0.12 0 0"/><mass value="0.6"/>
<inertia ixx="0.0004" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.004"/></inertial>
<collision><origin xyz="0.12 0 0"/><geometry><box size="0.24 0.05 0.05"/></geometry></collision></link>
<joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 1 0"/>
<limit lower="-2" upper="2" effort="20" velocity="5"/></joint>
<joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.15 0 0"/>
<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="20" velocity="5"/></joint></robot>"#
    )
}

/// A URDF naming `mesh` for its one link, in `dir`, and the check's
/// warnings and verdict for it with `package_paths`.
fn check_with(dir: &Path, mesh: &str, package_paths: &[PathBuf]) -> (Option<bool>, String) {
    let u = dir.join("r.urdf");
    let inertial = solid_box(1.0, [0.4, 0.2, 0.1], [0.0, 0.0, 0.0]);
    std::fs::write(&u, urdf(mesh, "1 1 1", "0 0 0", &inertial)).unwrap();
    let (_, rep) = check_urdf_file(&u, package_paths).unwrap();
    let w: Vec<String> = rep.warnings.iter().map(|w| w.to_string()).collect();
    (rep.links[0].realizable_in_geometry, w.join("\n"))
}

/// A mesh path that climbs out of its package or the URDF's folder, or an
/// absolute one elsewhere, is not read (the link is left unbounded, with a
/// warning naming the path) unless a package folder given holds it.
#[test]
fn a_mesh_path_outside_its_package_or_folder_is_not_read() {
    let d = dir("outside");
    let outside = d.join("outside");
    let share = d.join("share");
    let robot = d.join("robot");
    for f in [&outside, &share.join("my_robot"), &robot] {
        std::fs::create_dir_all(f).unwrap();
    }
    let (bv, bf) = box_mesh([0.4, 0.2, 0.1]);
    std::fs::write(outside.join("secret.stl"), stl_binary(&bv, &bf)).unwrap();
    let secret = outside.join("secret.stl").display().to_string();
    let cases = [
        "package://my_robot/../../outside/secret.stl".to_string(),
        "../outside/secret.stl".to_string(),
        secret.clone(),
        format!("file://{secret}"),
    ];
    for mesh in &cases {
        let (bounded, warnings) = check_with(&robot, mesh, std::slice::from_ref(&share));
        assert_eq!(bounded, None, "{mesh}: {warnings}");
        assert!(
            warnings.contains("leads outside") && warnings.contains("link 'body'"),
            "{mesh}: {warnings}"
        );
    }
    // a package folder that holds it allows an absolute or relative path to it
    for mesh in &cases[1..] {
        let (bounded, warnings) = check_with(&robot, mesh, std::slice::from_ref(&outside));
        assert_eq!(bounded, Some(true), "{mesh}: {warnings}");
    }
    let paths = MeshPaths {
        urdf_dir: robot.clone(),
        package_paths: vec![share.clone()],
        ros_package_path: false,
    };
    let e = paths.resolve(&cases[0]).unwrap_err();
    assert!(
        matches!(e, momentlmi::urdf::mesh::MeshError::Outside { .. }),
        "{e}"
    );
    // inside the package, `..` that stays in it is fine
    std::fs::create_dir_all(share.join("my_robot").join("meshes")).unwrap();
    std::fs::write(share.join("my_robot").join("b.stl"), stl_binary(&bv, &bf)).unwrap();
    assert!(paths.resolve("package://my_robot/meshes/../b.stl").is_ok());
}

/// A mesh path that names a folder or a FIFO says so (not "not found"),
/// and nothing waits on the FIFO.
#[test]
fn a_mesh_that_is_not_a_file_says_what_it_is() {
    let d = dir("notafile");
    std::fs::create_dir_all(d.join("folder.stl")).unwrap();
    let (bounded, warnings) = check_with(&d, "folder.stl", &[]);
    assert_eq!(bounded, None);
    assert!(warnings.contains("is a folder"), "{warnings}");
    #[cfg(unix)]
    {
        let fifo = d.join("fifo.stl");
        let c = std::ffi::CString::new(fifo.display().to_string()).unwrap();
        // SAFETY: a valid NUL-terminated path; mkfifo only creates the node.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let (bounded, warnings) = check_with(&d, "fifo.stl", &[]);
        assert_eq!(bounded, None);
        assert!(warnings.contains("is a FIFO"), "{warnings}");
        // a package's candidate that is a FIFO is named too
        let pkg = d.join("pkg");
        std::fs::create_dir_all(&pkg).unwrap();
        let f2 = std::ffi::CString::new(pkg.join("m.stl").display().to_string()).unwrap();
        // SAFETY: as above.
        assert_eq!(unsafe { libc::mkfifo(f2.as_ptr(), 0o600) }, 0);
        let (_, warnings) = check_with(&d, "package://pkg/m.stl", &[]);
        assert!(warnings.contains("is a FIFO"), "{warnings}");
    }
}

/// Bounding volumes kept in a cache folder: the first load writes one
/// entry per mesh and per covering solve, a second load gives the same
/// ellipsoids bit for bit without new entries, takes what the entries hold
/// (an entry replaced by another ellipsoid is what the next load returns),
/// and a damaged entry is solved again and rewritten.
#[test]
fn bounding_volumes_come_from_the_cache_when_it_holds_them() {
    use momentlmi::dynamics::robots::load_robot;
    use momentlmi::moments::Ellipsoid;
    use momentlmi::moments::cache::{CacheKey, SolveCache};
    let d = dir("cache");
    let (v, f) = box_mesh([0.3, 0.06, 0.06]);
    std::fs::write(d.join("upper.stl"), stl_binary(&v, &f)).unwrap();
    let extra = r#"<collision><origin xyz="0.2 0 0"/><geometry><sphere radius="0.05"/></geometry></collision>"#;
    let u = d.join("arm.urdf");
    std::fs::write(&u, two_link_arm(r#"<mesh filename="upper.stl"/>"#, extra)).unwrap();
    let cache = SolveCache::new(d.join("cache"));
    let load = || {
        let r = load_robot(u.to_str().unwrap(), None).unwrap();
        let r = r.with_bounding_cache(cache.clone());
        assert!(
            r.bounding_warnings().is_empty(),
            "{:?}",
            r.bounding_warnings()
        );
        r.bounding().to_vec()
    };
    let entries = || {
        let mut e: Vec<PathBuf> = std::fs::read_dir(cache.dir())
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        e.sort();
        e
    };
    let uncached = load_robot(u.to_str().unwrap(), None)
        .unwrap()
        .bounding()
        .to_vec();
    let first = load();
    assert_eq!(first, uncached);
    // the mesh's ellipsoid and the upper body's cover (the fore box is one shape)
    assert_eq!(entries().len(), 2, "{:?}", entries());
    assert_eq!(load(), first);
    assert_eq!(entries().len(), 2);
    // damaged entries: solved again, rewritten as they were
    let kept: Vec<Vec<u8>> = entries()
        .iter()
        .map(|p| std::fs::read(p).unwrap())
        .collect();
    for p in entries() {
        std::fs::write(&p, b"not an entry").unwrap();
    }
    assert_eq!(load(), first);
    let rewritten: Vec<Vec<u8>> = entries()
        .iter()
        .map(|p| std::fs::read(p).unwrap())
        .collect();
    assert_eq!(rewritten, kept);
    // the entries are what a load takes: the mesh's replaced by a ball
    // (which covers the sphere) makes the cover that ball, newly solved
    let ball = |r: f64| {
        Ellipsoid::new(
            nalgebra::Vector3::new(0.1, 0.0, 0.0),
            nalgebra::Vector3::repeat(r),
        )
        .unwrap()
    };
    let put = |p: &Path, e: &Ellipsoid| {
        let stem = p.file_stem().unwrap().to_str().unwrap();
        cache.put(&CacheKey::from_hex(stem).unwrap(), e).unwrap();
    };
    let before = entries();
    before.iter().for_each(|p| put(p, &ball(0.5)));
    let upper = load()[0].clone();
    assert_eq!(upper.len(), 1);
    assert!(
        (upper[0].semi_axes - ball(0.5).semi_axes).abs().max() < 1e-5,
        "{upper:?}"
    );
    // and the new cover's entry, replaced, is what the next load returns
    let new: Vec<PathBuf> = entries()
        .into_iter()
        .filter(|p| !before.contains(p))
        .collect();
    assert_eq!(new.len(), 1);
    put(&new[0], &ball(0.7));
    assert_eq!(load()[0], vec![ball(0.7)]);
}

/// A binary STL whose header begins with "solid" (as CAD exporters name
/// the part there; Solo12's feet) reads as the binary file it is.
#[test]
fn a_binary_stl_whose_header_says_solid_is_read_as_binary() {
    let d = dir("stl-solid-header");
    let (bv, bf) = box_mesh([0.1, 0.2, 0.3]);
    let plain = stl_binary(&bv, &bf);
    let mut named = plain.clone();
    named[..14].copy_from_slice(b"solid foot_stl");
    let (p, n) = (d.join("plain.stl"), d.join("named.stl"));
    std::fs::write(&p, &plain).unwrap();
    std::fs::write(&n, &named).unwrap();
    let v = read_vertices(&n).expect("a binary STL named 'solid …'");
    assert_eq!(v, read_vertices(&p).unwrap());
    assert!(!v.is_empty());
}
