//! The stator seams: general FE stators, stators with mass, several nodes in contact at once.

use rubsim::analysis::{self, Keep, RunSettings};
use rubsim::model::Model;
use rubsim::scene;
use std::path::Path;

const PAPER: &str = include_str!("../scenes/paper/partial_rub.toml");

fn base() -> String {
    PAPER.replace("[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1", "")
}

/// The base scene with the rod's clearance given in metres.
fn base_si() -> String {
    base().replace("clearance_nd = 0.6 ", "clearance = 1.2e-4")
}

fn run(text: &str, ov: &[&str], nu: f64) -> analysis::SpeedResults {
    let mut o: Vec<String> = ov.iter().map(|s| s.to_string()).collect();
    o.push("run.error_estimate=false".into());
    o.push(format!("run.speed_ratio={nu}"));
    let ls = scene::parse(Path::new("t.toml"), text, &o).expect("scene");
    let model = Model::from_scene(&ls).expect("model");
    let s = RunSettings::from_run(&ls.scene.run, "y");
    analysis::run_speed(&model, &s, nu, Keep::default()).expect("run")
}

/// The paper's rod written as a general FE stator: 3 bar elements, base fixed, lateral DOFs
/// guided. k_s = E A / L = 25 k_r with k_r = 48EI/L³ of the Table 1 shaft.
fn fe_rod(clearance: f64, density: f64) -> String {
    let kr = 48.0 * 200e9 * (std::f64::consts::PI * 0.01_f64.powi(4) / 64.0) / 0.4_f64.powi(3);
    let e = 25.0 * kr * 0.04 / 25e-6;
    let y0 = 0.06 + clearance;
    let nodes: Vec<String> = (0..4)
        .map(|i| format!("[0.0, {}]", y0 + 0.04 * i as f64 / 3.0))
        .collect();
    let els: Vec<String> = (0..3)
        .map(|i| format!("{{ kind = \"bar\", nodes = [{i}, {}], youngs_modulus = {e}, area = 25e-6, density = {density} }}", i + 1))
        .collect();
    let stator = format!(
        "[[stator]]\nkind = \"fe\"\nname = \"rod\"\nstation = \"disk\"\nnodes = [{}]\nelements = [{}]\nfixed = [[0, 0], [1, 0], [2, 0], [3, 0], [3, 1]]\ncontact_nodes = [0]\n",
        nodes.join(", "),
        els.join(", ")
    );
    let t = base();
    let a = t.find("[[stator]]").unwrap();
    let b = t.find("[run]").unwrap();
    format!("{}{}\n{}", &t[..a], stator, &t[b..])
}

#[test]
fn fe_stator_reproduces_the_rod() {
    let rod = run(&base_si(), &["stator.0.elements=3"], 1.7);
    let fe = run(&fe_rod(1.2e-4, 0.0), &[], 1.7);
    for i in 0..4 {
        assert!(
            (rod.extents_nd[i] - fe.extents_nd[i]).abs() < 1e-9,
            "{:?} vs {:?}",
            rod.extents_nd,
            fe.extents_nd
        );
    }
    assert_eq!(rod.period, fe.period);
}

#[test]
fn light_stator_with_mass_approaches_the_massless_one() {
    // Forward increment couples rotor and stator masses; a rod of small density behaves like
    // the massless rod (its axial modes are far above the rotor's).
    let fi = "run.integrator=\"forward_increment\"";
    let massless = run(
        &base_si(),
        &["stator.0.elements=3", fi, "run.harmonics=16"],
        1.7,
    );
    let massive = run(
        &base_si(),
        &[
            "stator.0.elements=3",
            "stator.0.density=20.0",
            fi,
            "run.harmonics=16",
        ],
        1.7,
    );
    let span = massless.extents_nd[3] - massless.extents_nd[2];
    for i in 0..4 {
        assert!(
            (massless.extents_nd[i] - massive.extents_nd[i]).abs() < 0.05 * span,
            "{:?} vs {:?}",
            massless.extents_nd,
            massive.extents_nd
        );
    }
    assert!(massive.stats.min_gap >= -1e-12, "{}", massive.stats.min_gap);
}

#[test]
fn ring_with_mass_runs_and_does_not_penetrate() {
    let t = base();
    let a = t.find("[[stator]]").unwrap();
    let b = t.find("[run]").unwrap();
    let ring = "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"disk\"\nclearance_nd = 0.8\nstiffness_ratio = 25.0\nmass = 0.5\ndamping = 50.0\n";
    let text = format!("{}{}\n{}", &t[..a], ring, &t[b..]);
    let r = run(&text, &["run.integrator=\"forward_increment\""], 1.2);
    assert!(r.stats.contact_steps > 0);
    assert!(
        r.stats.min_gap >= -1e-6 * r.clearances[0],
        "{}",
        r.stats.min_gap
    );
}

#[test]
fn several_nodes_in_contact_at_once() {
    // An arc of 9 nodes above the rotor, each on a radial spring: the rotor presses several
    // of them together, so the complementarity solve has several active pairs.
    let n = 9;
    let r0 = 0.06 + 1.0e-4;
    let mut nodes = Vec::new();
    let mut els = Vec::new();
    for i in 0..n {
        let th = std::f64::consts::FRAC_PI_2 + (i as f64 - 4.0) * 0.002;
        nodes.push(format!("[{}, {}]", r0 * th.cos(), r0 * th.sin()));
        els.push(format!(
            "{{ kind = \"spring\", node = {i}, stiffness = 2.0e5, angle_deg = {} }}",
            th.to_degrees()
        ));
        els.push(format!(
            "{{ kind = \"spring\", node = {i}, stiffness = 2.0e5, angle_deg = {} }}",
            th.to_degrees() + 90.0
        ));
    }
    let contact: Vec<String> = (0..n).map(|i| i.to_string()).collect();
    let stator = format!(
        "[[stator]]\nkind = \"fe\"\nname = \"arc\"\nstation = \"disk\"\nnodes = [{}]\nelements = [{}]\nfixed = []\ncontact_nodes = [{}]\n",
        nodes.join(", "),
        els.join(", "),
        contact.join(", ")
    );
    let t = base();
    let a = t.find("[[stator]]").unwrap();
    let b = t.find("[run]").unwrap();
    let text = format!("{}{}\n{}", &t[..a], stator, &t[b..]);
    for kind in ["collocated", "forward_increment"] {
        let r = run(&text, &[&format!("run.integrator=\"{kind}\"")], 1.7);
        assert!(
            r.stats.max_active >= 2,
            "{kind}: max active {}",
            r.stats.max_active
        );
        assert!(
            r.stats.min_gap >= -1e-9 * r.clearances[0],
            "{kind}: {}",
            r.stats.min_gap
        );
    }
}

#[test]
fn collocated_run_records_the_forces_of_a_stator_with_mass() {
    // Collocated runs solve stators with mass by forward increment inside the step; with no
    // massless stator the two integrators take the same steps, so the collocated run must
    // report the same contact forces (before the fix it recorded none: only massless-stator
    // forces reached its record).
    let massive = ["stator.0.elements=3", "stator.0.density=20.0"];
    let mut col = massive.to_vec();
    col.push("run.integrator=\"collocated\"");
    let mut fi = massive.to_vec();
    fi.push("run.integrator=\"forward_increment\"");
    let c = run(&base_si(), &col, 1.7);
    let f = run(&base_si(), &fi, 1.7);
    assert!(c.stats.contact_steps > 0);
    assert!(c.contact_force_max_nd > 0.0, "{}", c.contact_force_max_nd);
    assert_eq!(c.extents_nd, f.extents_nd);
    assert!(
        (c.contact_force_max_nd - f.contact_force_max_nd).abs() <= 1e-12 * f.contact_force_max_nd,
        "collocated {} vs forward increment {}",
        c.contact_force_max_nd,
        f.contact_force_max_nd
    );
    assert_eq!(c.contact_fraction, f.contact_fraction);
    assert_eq!(c.stats.contact_steps, f.stats.contact_steps);
}
