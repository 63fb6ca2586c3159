//! URDF import checked against an independent library: the Panda arm
//! (finger joints locked), with reference values copied from Pinocchio
//! 4.1.0, a URDF written here from the Panda's kinematics, fixed-joint
//! merging, the sidecar, and errors naming the element.

use momentlmi::dynamics::urdf::{Sidecar, model_from_urdf_str};
use momentlmi::dynamics::{Data, crba, regressor, rnea};
use momentlmi::moments::InertialParams;
use std::path::Path;

struct Case7 {
    q: [f64; 7],
    qd: [f64; 7],
    qdd: [f64; 7],
    tau: [f64; 7],
    y0: [f64; 70],
    m: [[f64; 7]; 7],
}

const PANDA_PARAMS: [[f64; 10]; 7] = [
    [
        4.970684,
        0.0192614005,
        0.010343993404000001,
        -0.23670397208000002,
        0.7146633690007234,
        -0.0001790829744405,
        0.007689227891810001,
        0.7179564810773871,
        0.019661580965898477,
        0.009213163777211224,
    ],
    [
        0.646926,
        -0.002031994566,
        -0.018579714719999998,
        0.0022610063699999997,
        0.00850351162402155,
        -0.00398335888393552,
        0.01026110182100817,
        0.028124284712194955,
        0.0007689361029464,
        0.026534991901690206,
    ],
    [
        3.228604,
        0.088844724872,
        0.126729164208,
        -0.214708623208,
        0.05649492601407083,
        -0.008248333140675744,
        -0.005487648106562255,
        0.05287838199960611,
        -0.0043772571218395825,
        0.01824920229252011,
    ],
    [
        3.587895,
        -0.19076837714999995,
        0.3746444080049999,
        0.09850206932999996,
        0.06767727025085987,
        0.027715843173625836,
        0.003905355026276097,
        0.032399430424451314,
        -0.0016444875773692635,
        0.07758614905253955,
    ],
    [
        1.225946,
        -0.014653732538,
        0.05034347249,
        -0.047121686402,
        0.03942757095803552,
        -0.0015152444733270301,
        -0.004600245517563105,
        0.03146037232526039,
        0.0021640520520981297,
        0.010869510762828563,
    ],
    [
        1.666555,
        0.10024161669500001,
        -0.023526756935,
        -0.017527158935000002,
        0.00248046035817079,
        0.001524110902883315,
        -0.00010375891721868492,
        0.010567766133106952,
        9.3569097314605e-05,
        0.01179456023023895,
    ],
    [
        1.4955219999999998,
        0.0025736053713382055,
        0.002034439958661797,
        0.150277948634,
        0.031633343190949584,
        0.0003913912816842479,
        -0.000965305169919112,
        0.02921239941242836,
        -0.0012555365982728983,
        0.006684151967360946,
    ],
];
const PANDA_CASES: [Case7; 2] = [
    Case7 {
        q: [
            -1.4411215290686077,
            1.0920753239976442,
            1.2299518179586753,
            -2.079907434992082,
            -0.041272797069959566,
            3.197385143440179,
            -1.7650676157541152,
        ],
        qd: [
            -0.032925137580279706,
            -0.9887677991601671,
            -0.6510173531801278,
            -0.7391017065038881,
            -0.2759093808084856,
            -2.014788093293679,
            -0.576977927108488,
        ],
        qdd: [
            12.566994727496962,
            19.39145275416727,
            -13.730785222186611,
            13.250576534543825,
            6.922328229090759,
            11.109742671611436,
            1.4136681865936076,
        ],
        tau: [
            -1.2417407962485028,
            -3.838474590547663,
            -0.5556655986492802,
            6.780183588019828,
            1.0800271701558881,
            0.7597613660749138,
            0.21455692168456686,
        ],
        y0: [
            0.0,
            0.0,
            -0.0,
            0.0,
            -0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            12.566994727496962,
            0.0,
            0.0,
            0.0,
            0.0,
            9.92698506204643,
            10.238827347147506,
            -17.66191328639779,
            2.6400096654505303,
            -8.064805112283612,
            4.307318390850412e-15,
            0.9912690203557089,
            -2.724942932024109,
            -0.31322414981799285,
            6.273854559213346,
            -4.022128059887619,
            8.205834634270797,
            8.623237126658566,
            13.949113121934051,
            0.9912156639809906,
            -4.256341527335978,
            0.8324326551294531,
            -0.6021875207161357,
            -2.8833699085158124,
            0.9902055071453346,
            -0.2536814386718022,
            -5.461646986921484,
            1.4433504443886365,
            -8.024788148551794,
            -13.085571431245631,
            2.4046441401090366,
            -0.11920564488154534,
            4.348038304816516,
            -7.872791407494469,
            -1.6820164302330378,
            -0.3865493812788339,
            -2.013769825820645,
            -7.735993371503232,
            2.5375120827160713,
            18.660876655940058,
            -11.107314427707927,
            -0.11920564488154534,
            -7.399420606240679,
            7.5649927721718395,
            7.872791407494466,
            -0.4588355848102257,
            -11.653477178238214,
            5.257215898090412,
            -11.035028224176529,
            22.09188941354067,
            -8.063414838365178,
            -0.918253001307048,
            -7.0972210960149065,
            -12.043680934518473,
            -8.590498763856802,
            -7.278278876128808,
            -5.256817153976424,
            21.08321947899434,
            -1.2439715470465915,
            15.416059571289292,
            -10.784475089167694,
        ],
        m: [
            [
                2.1503474161520475,
                -0.003843070374834834,
                0.8492082057784354,
                -0.889544178491906,
                -0.11189838390912313,
                -0.16574333761875296,
                -0.005672794201687984,
            ],
            [
                -0.003843070374834834,
                1.0446788491199896,
                -0.7414030476027806,
                -0.32519884344479905,
                0.06928354903665189,
                -0.06618070208727656,
                0.0048989728699258975,
            ],
            [
                0.8492082057784354,
                -0.7414030476027806,
                1.391849859464016,
                -0.012090641499246092,
                -0.14660499792397289,
                0.004771017588391952,
                -0.004512795651902467,
            ],
            [
                -0.889544178491906,
                -0.32519884344479905,
                -0.012090641499246092,
                0.9703862860970583,
                0.030617727084522026,
                0.1368799528110521,
                0.0023708819476725576,
            ],
            [
                -0.11189838390912313,
                0.06928354903665189,
                -0.14660499792397289,
                0.030617727084522026,
                0.041733257754543646,
                0.0010803491788365799,
                0.006863791636956811,
            ],
            [
                -0.16574333761875296,
                -0.06618070208727656,
                0.004771017588391952,
                0.1368799528110521,
                0.0010803491788365799,
                0.05533115673554366,
                0.0011895297650112325,
            ],
            [
                -0.005672794201687984,
                0.0048989728699258975,
                -0.004512795651902467,
                0.0023708819476725576,
                0.006863791636956811,
                0.0011895297650112325,
                0.006684151967360946,
            ],
        ],
    },
    Case7 {
        q: [
            2.5886110217107112,
            1.5186493986088911,
            -1.6988570561487597,
            -2.3539474078466536,
            -1.997382925058409,
            1.1040979954632875,
            2.2590785481856908,
        ],
        qd: [
            2.21349020229371,
            -2.5677509360345225,
            -2.094129351893976,
            -0.7611330885690122,
            0.5881296980851629,
            -0.8235805725369763,
            0.3727221194713497,
        ],
        qdd: [
            -2.2563228424949777,
            2.81001597689448,
            1.394772648562931,
            9.721289218326412,
            -4.880903004462226,
            9.334571442663954,
            -16.36214704198549,
        ],
        tau: [
            -13.839900435700573,
            -20.91722105900986,
            -14.858560395373097,
            -6.659816993494522,
            0.224012980874019,
            1.3027027245849614,
            -0.09630112830980696,
        ],
        y0: [
            0.0,
            0.0,
            -0.0,
            0.0,
            -0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            -2.2563228424949777,
            0.0,
            0.0,
            0.0,
            1.1102230246251565e-16,
            -2.841892850576561,
            11.070722160588344,
            -3.1498630777155214,
            0.5855700080815831,
            6.437914953639105,
            6.106226635438361e-16,
            -0.2837800524871731,
            -1.299388961395478,
            3.803697843085293,
            -1.7960762815643856,
            5.920477639136861,
            -2.4561265071399774,
            4.1119903841629,
            -8.76237048971342,
            -12.037018490776244,
            -4.71162298307648,
            -0.48268700987647595,
            1.6823252395456478,
            -3.391265565741322,
            -4.006328279924342,
            2.989272878567927,
            -10.813341906849562,
            -11.618316681804735,
            -1.7804182225075487,
            -6.51719196782607,
            1.1705277441802395,
            -1.6570549974328157,
            -4.60364882093025,
            5.697682306414721,
            -1.0886393947858204,
            6.027624814939248,
            -10.44244526983772,
            -4.837381817650868,
            -1.8678241921910816,
            -18.124517854847433,
            -2.3055121379225767,
            -1.6570549974328168,
            -6.461518009962513,
            6.1887601888635855,
            -5.697682306414719,
            -0.01587043973491639,
            0.34970183396425947,
            24.892115692227723,
            3.7379831167515842,
            -9.15800606820898,
            -7.694477758667485,
            -2.2563076768165145,
            -2.7818304982344197,
            16.45834608740986,
            -6.157986427474729,
            -16.055215286052263,
            1.835583919803147,
            16.040561042303008,
            8.34486708764986,
            -2.7696262691707214,
            -9.489814640016604,
        ],
        m: [
            [
                1.5680239824355482,
                0.24691503787268937,
                -0.009309497433010863,
                0.6823479905603849,
                -0.06071455664400503,
                -0.11993508748350362,
                0.005594129642825461,
            ],
            [
                0.24691503787268937,
                0.7154209837953138,
                0.39154215203353004,
                0.18719647117608837,
                -0.04450461445795824,
                -0.03732144211223214,
                -0.0002822990800700368,
            ],
            [
                -0.009309497433010863,
                0.39154215203353004,
                1.0782283534795287,
                0.05046088793587337,
                -0.05939645530533573,
                0.08228859294950926,
                0.002523785309683109,
            ],
            [
                0.6823479905603849,
                0.18719647117608837,
                0.05046088793587337,
                0.8835766813602981,
                -0.10393150122473137,
                -0.06389368098223672,
                0.004712592359767533,
            ],
            [
                -0.06071455664400503,
                -0.04450461445795824,
                -0.05939645530533573,
                -0.10393150122473137,
                0.053535142957877056,
                -0.0012567647254946356,
                -0.0014669278239603262,
            ],
            [
                -0.11993508748350362,
                -0.03732144211223214,
                0.08228859294950926,
                -0.06389368098223672,
                -0.0012567647254946356,
                0.05308409251118726,
                5.198901748319019e-05,
            ],
            [
                0.005594129642825461,
                -0.0002822990800700368,
                0.002523785309683109,
                0.004712592359767533,
                -0.0014669278239603262,
                5.198901748319019e-05,
                0.006684151967360946,
            ],
        ],
    },
];

/// Panda joint origins (xyz, rpy) and limits, from its URDF; all axes z.
const JOINTS: [([f64; 3], [f64; 3]); 7] = [
    ([0.0, 0.0, 0.333], [0.0, 0.0, 0.0]),
    ([0.0, 0.0, 0.0], [-std::f64::consts::FRAC_PI_2, 0.0, 0.0]),
    ([0.0, -0.316, 0.0], [std::f64::consts::FRAC_PI_2, 0.0, 0.0]),
    ([0.0825, 0.0, 0.0], [std::f64::consts::FRAC_PI_2, 0.0, 0.0]),
    (
        [-0.0825, 0.384, 0.0],
        [-std::f64::consts::FRAC_PI_2, 0.0, 0.0],
    ),
    ([0.0, 0.0, 0.0], [std::f64::consts::FRAC_PI_2, 0.0, 0.0]),
    ([0.088, 0.0, 0.0], [std::f64::consts::FRAC_PI_2, 0.0, 0.0]),
];

fn inertial_xml(p: &InertialParams) -> String {
    let (m, c, i) = p.to_urdf();
    format!(
        "<inertial><origin xyz=\"{:e} {:e} {:e}\" rpy=\"0 0 0\"/><mass value=\"{m:e}\"/><inertia ixx=\"{:e}\" ixy=\"{:e}\" ixz=\"{:e}\" iyy=\"{:e}\" iyz=\"{:e}\" izz=\"{:e}\"/></inertial>",
        c[0], c[1], c[2], i[0], i[1], i[2], i[3], i[4], i[5]
    )
}

/// A URDF with the Panda's joints and the reference (merged) body
/// parameters; the last body is split into two links joined by a fixed
/// joint, so the import must merge them back.
fn panda_like_urdf() -> String {
    let mut s = String::from("<robot name=\"panda_like\">\n<link name=\"l0\"/>\n");
    for (k, (xyz, rpy)) in JOINTS.iter().enumerate() {
        let p = InertialParams(PANDA_PARAMS[k]);
        let body = if k < 6 {
            inertial_xml(&p)
        } else {
            // split: half the mass stays, the rest moves to a fixed child 0.1 m up z
            let half = InertialParams(PANDA_PARAMS[k].map(|v| 0.5 * v));
            inertial_xml(&half)
        };
        s += &format!(
            "<link name=\"l{}\">{body}</link>\n<joint name=\"j{}\" type=\"revolute\"><parent link=\"l{k}\"/><child link=\"l{}\"/><origin xyz=\"{} {} {}\" rpy=\"{} {} {}\"/><axis xyz=\"0 0 1\"/><limit lower=\"-2.8\" upper=\"2.8\" effort=\"1\" velocity=\"1\"/></joint>\n",
            k + 1,
            k + 1,
            k + 1,
            xyz[0],
            xyz[1],
            xyz[2],
            rpy[0],
            rpy[1],
            rpy[2]
        );
    }
    // the other half, expressed in a frame 0.1 m up z and rotated about z
    let half = InertialParams(PANDA_PARAMS[6].map(|v| 0.5 * v));
    let r = momentlmi::moments::rpy_rotation([0.0, 0.0, 0.7]);
    let shift = nalgebra::Vector3::new(0.0, 0.0, 0.1);
    // x_l7 = R x_tip + shift  ⇒  x_tip = Rᵀ (x_l7 − shift)
    let tip = half.transformed(&r.transpose(), &(-(r.transpose() * shift)));
    s += &format!("<link name=\"tip\">{}</link>\n", inertial_xml(&tip));
    s += "<joint name=\"fix\" type=\"fixed\"><parent link=\"l7\"/><child link=\"tip\"/><origin xyz=\"0 0 0.1\" rpy=\"0 0 0.7\"/></joint>\n";
    s += "<link name=\"massless\"/><joint name=\"fix2\" type=\"fixed\"><parent link=\"tip\"/><child link=\"massless\"/></joint>\n</robot>\n";
    s
}

fn max_abs_diff(a: impl IntoIterator<Item = f64>, b: impl IntoIterator<Item = f64>) -> f64 {
    a.into_iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn panda_like_urdf_matches_reference_dynamics() {
    let model = model_from_urdf_str(&panda_like_urdf(), "panda_like.urdf", None).unwrap();
    assert_eq!(model.dof(), 7);
    assert_eq!(
        model.joint_names(),
        vec!["j1", "j2", "j3", "j4", "j5", "j6", "j7"]
    );
    // the fixed tip was merged back: the last body equals the reference
    assert!(max_abs_diff(model.params(), PANDA_PARAMS.iter().flatten().copied()) < 1e-12);
    let mut data = Data::new(&model);
    for (k, c) in PANDA_CASES.iter().enumerate() {
        let tau = rnea(&model, &mut data, &c.q, &c.qd, &c.qdd)
            .unwrap()
            .clone();
        assert!(
            max_abs_diff(tau.iter().copied(), c.tau) < 1e-9,
            "case {k}: {tau:?}"
        );
        let y = regressor(&model, &mut data, &c.q, &c.qd, &c.qdd)
            .unwrap()
            .clone();
        assert!(
            max_abs_diff((0..70).map(|j| y[(0, j)]), c.y0) < 1e-9,
            "case {k}: regressor row 0"
        );
        let m = crba(&model, &mut data, &c.q).unwrap().clone();
        for i in 0..7 {
            assert!(
                max_abs_diff((0..7).map(|j| m[(i, j)]), c.m[i]) < 1e-9,
                "case {k}: mass row {i}"
            );
        }
    }
}

#[test]
fn panda_urdf_from_shared_matches_all_reference_cases() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/reference");
    let (Ok(urdf), Ok(json)) = (
        std::fs::read_to_string(dir.join("panda.urdf")),
        std::fs::read_to_string(dir.join("rnea_panda.json")),
    ) else {
        println!("skipping: ../shared/reference not found");
        return;
    };
    let sc = Sidecar::parse(
        "lock = [\"panda_finger_joint1\", \"panda_finger_joint2\"]\n",
        "sidecar.toml",
    )
    .unwrap();
    let model = model_from_urdf_str(&urdf, "panda.urdf", Some(&sc)).unwrap();
    assert_eq!(model.dof(), 7);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let params: Vec<f64> = v["body_parameters"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|b| b.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect();
    assert!(
        max_abs_diff(model.params(), params) < 1e-12,
        "merged body parameters"
    );
    let vec_of = |x: &serde_json::Value| -> Vec<f64> {
        x.as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    let mut data = Data::new(&model);
    for (k, c) in v["cases"].as_array().unwrap().iter().enumerate() {
        let (q, qd, qdd) = (vec_of(&c["q"]), vec_of(&c["qd"]), vec_of(&c["qdd"]));
        let tau = rnea(&model, &mut data, &q, &qd, &qdd).unwrap().clone();
        assert!(
            max_abs_diff(tau.iter().copied(), vec_of(&c["tau"])) < 1e-9,
            "case {k}"
        );
        let y = regressor(&model, &mut data, &q, &qd, &qdd).unwrap().clone();
        for (i, row) in c["regressor_rows"].as_array().unwrap().iter().enumerate() {
            assert!(
                max_abs_diff((0..70).map(|j| y[(i, j)]), vec_of(row)) < 1e-9,
                "case {k} row {i}"
            );
        }
        let m = crba(&model, &mut data, &q).unwrap().clone();
        for (i, row) in c["mass_matrix"].as_array().unwrap().iter().enumerate() {
            assert!(
                max_abs_diff((0..7).map(|j| m[(i, j)]), vec_of(row)) < 1e-9,
                "case {k} mass row {i}"
            );
        }
    }
}

#[test]
fn sidecar_rotor_and_transmission() {
    let urdf = "<robot name=\"r\"><link name=\"base\"/><link name=\"arm\"><inertial><mass value=\"1\"/><origin xyz=\"0.1 0 0\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\
        <joint name=\"j\" type=\"continuous\"><parent link=\"base\"/><child link=\"arm\"/><axis xyz=\"0 0 2\"/></joint>\
        <transmission name=\"t\"><type>transmission_interface/SimpleTransmission</type><joint name=\"j\"/><actuator name=\"m\"><mechanicalReduction>9</mechanicalReduction></actuator></transmission></robot>";
    let sc = Sidecar::parse(
        "[[rotor]]\njoint = \"j\"\nmass = 0.3\ninertia = [1e-4, 0, 0, 1e-4, 0, 2e-4]\n",
        "s.toml",
    )
    .unwrap();
    let m = model_from_urdf_str(urdf, "r.urdf", Some(&sc)).unwrap();
    assert_eq!(m.rotors.len(), 1);
    assert_eq!(m.rotors[0].gear_ratio, 9.0);
    assert_eq!(m.joints[0].limits, (f64::NEG_INFINITY, f64::INFINITY));
    assert!((m.joints[0].axis.norm() - 1.0).abs() < 1e-15);
    // reflected inertia: M = I_arm,zz(origin) + N² I_rotor,zz
    let mut d = Data::new(&m);
    let mm = crba(&m, &mut d, &[0.3]).unwrap();
    assert!(
        (mm[(0, 0)] - (0.01 + 1.0 * 0.01 + 81.0 * 2e-4)).abs() < 1e-12,
        "{}",
        mm[(0, 0)]
    );
}

#[test]
fn malformed_input_names_the_element() {
    let cases = [
        (
            "<robot name=\"r\"><link name=\"a\"></robot>",
            "malformed XML",
        ),
        (
            "<robot name=\"r\"><link name=\"a\"/><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"nope\"/></joint></robot>",
            "<joint name=\"j\">: child link 'nope' does not exist",
        ),
        (
            "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/></robot>",
            "expected one root link",
        ),
        (
            "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"f\" type=\"floating\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>",
            "<joint name=\"f\">: type Floating is not supported",
        ),
        (
            "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 0\"/></joint></robot>",
            "<joint name=\"j\">: axis must be a non-zero vector",
        ),
    ];
    for (text, want) in cases {
        let e = model_from_urdf_str(text, "bad.urdf", None)
            .unwrap_err()
            .to_string();
        assert!(e.contains(want) && e.contains("bad.urdf"), "{e}");
    }
    assert!(
        Sidecar::parse("[[rotor]]\njoint = 3\n", "s.toml")
            .unwrap_err()
            .to_string()
            .contains("s.toml")
    );
    assert!(
        Sidecar::parse("gravty = [0, 0, -9.81]\n", "s.toml").is_err(),
        "unknown keys are rejected"
    );
    let ok = "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"1 0 0\"/></joint></robot>";
    let sc = Sidecar::parse(
        "[[rotor]]\njoint = \"j\"\nmass = 0.1\ninertia = [1, 0, 0, 1, 0, 1]\n",
        "s.toml",
    )
    .unwrap();
    let e = model_from_urdf_str(ok, "ok.urdf", Some(&sc))
        .unwrap_err()
        .to_string();
    assert!(e.contains("no gear_ratio"), "{e}");
}
