//! The reader never panics: random texts built from the language's significant pieces, and
//! every prefix-truncation of a real-shaped dataset, must give a value or diagnostics.

use linkage_adm::{parse_commands, parse_dataset, parse_typed_commands};
use std::sync::Arc;

/// Small deterministic generator (64-bit LCG), so failures reproduce.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 33) as usize
    }
}

const PIECES: &[&str] = &[
    "PART",
    "MARKER",
    "JOINT",
    "JPRIM",
    "MOTION",
    "COUPLER",
    "GEAR",
    "GCON",
    "UNITS",
    "ACCGRAV",
    "SFORCE",
    "REQUEST",
    "VARIABLE",
    "END",
    "STOP",
    "sim",
    "LEO",
    "/",
    "/1",
    "/01",
    ",",
    ", ",
    "\n",
    "\r\n",
    "\r",
    "\n,",
    "\n, ",
    "&",
    " &\n",
    ";",
    "!",
    "! adams_view_name='x'\n",
    "=",
    " = ",
    ":",
    "\\",
    "(",
    ")",
    "[",
    "]",
    "\"",
    "1",
    "-0.5",
    ".4",
    "90D",
    "1.0E-04",
    "1.0D0",
    "20 D",
    "I",
    "J",
    "QP",
    "REULER",
    "IP",
    "FUNCTION",
    "FUN",
    "F2",
    "FX",
    "X",
    "B3",
    "GROUND",
    "REVOLUTE",
    "INLINE",
    "ROTATIONAL",
    "JOINT",
    "JOINTS",
    "TYPE",
    "R:T",
    "SCALES",
    "FORCE",
    "NEWTON",
    "POUND",
    "EXACT",
    "X:Y:PSI",
    "C",
    "USER(",
    "IF(x: 1, 2, 3)",
    "\t",
    " ",
    "é",
    "\u{0}",
];

fn random_text(rng: &mut Lcg) -> String {
    let n = rng.next() % 60;
    (0..n).map(|_| PIECES[rng.next() % PIECES.len()]).collect()
}

#[test]
fn random_texts_never_panic() {
    let mut rng = Lcg(0x5eed);
    for _ in 0..20_000 {
        let text = random_text(&mut rng);
        let _ = parse_dataset(Arc::from("fuzz.adm"), &text);
        let _ = parse_commands(Arc::from("fuzz.acf"), &text);
    }
}

const SAMPLE: &str = "ADAMS/View model name: m\r\n!  adams_view_name='ground'\r\nPART/01, GROUND\r\n\
MARKER/0102, PART = 01, QP = 0, -.4, 0\r\n, REULER = 180D, 90D, 180D\r\nPART/02, MASS = 1\r\n\
, CM = 0201, IP = 0.04, 0.1, 0.1\r\nMARKER/0201, QP = 2, 0, 0\r\nJOINT/1, REVOLUTE, I = 0102, J = 0201\r\n\
MOTION/1, ROTATIONAL, JOINT = 1, FUNCTION = IF(time-1: 0,\r\n, 30D*time, STEP(time, 1, 0, 2, 1))\r\n\
REQUEST/05, F2=JOINT(1,0,2,0)\\F3=JOINT(1,0,3,0),C=RForce X Y Z\r\nCOUPLER/1, JOINTS = 1, 2, TYPE = R:R, SCALES = 1, 2\r\n\
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\r\nACCGRAV/KGRAV = -9.80665\r\nEND\r\n";

#[test]
fn every_truncation_of_a_dataset_is_handled() {
    let ok = parse_dataset(Arc::from("sample.adm"), SAMPLE);
    assert!(ok.is_ok(), "{:?}", ok.err());
    for (k, _) in SAMPLE.char_indices() {
        let _ = parse_dataset(Arc::from("sample.adm"), &SAMPLE[..k]);
        let _ = parse_dataset(Arc::from("sample.adm"), &SAMPLE[k..]);
    }
}

/// Pieces of command files, for [`random_command_files_never_panic`].
const COMMAND_PIECES: &[&str] = &[
    "\n",
    "\r\n",
    ",",
    "=",
    "/",
    "&",
    "!",
    " ",
    ":",
    "SIMULATE/",
    "sim/dyn",
    "sim/stat",
    "INITIAL_CONDITIONS",
    "VEL",
    "END",
    "DURATION",
    "STEPS",
    "DTOUT",
    "DEACTIVATE/",
    "ACTIVATE/",
    "JOINT",
    "S",
    "RANGE",
    "ID",
    "LINEAR/",
    "EIGENSOL",
    "STATEMAT",
    "COORDS",
    "FILE",
    "FORMAT",
    "equil/",
    "int/",
    "IC/",
    "KIN/",
    "alim",
    "PATTERN",
    "T:F",
    "METHOD",
    "ADV",
    "VARIABLE/1",
    "MARKER/2",
    "FUNC",
    "STEP(TIME,0,0,1,1)",
    "ENVIRONMENT/",
    "NAME",
    "VALUE",
    "UNSET",
    "DEBUG/",
    "EPRINT",
    "OUTPUT/",
    "PREF/",
    "NTHREADS",
    "FILE/",
    "MODEL",
    "COMMAND",
    "SAVE/",
    "SYSTEM",
    "accg/",
    "kgrav",
    "STOP",
    "1",
    "-1",
    "0",
    "2.5",
    "1D",
    "1e400",
    "99999999999999999999",
    "\"x\"",
];

#[test]
fn random_command_files_never_panic() {
    let mut rng = Lcg(0xacf);
    for _ in 0..20_000 {
        let n = rng.next() % 40;
        let text: String = (0..n)
            .map(|_| COMMAND_PIECES[rng.next() % COMMAND_PIECES.len()])
            .collect();
        let _ = parse_typed_commands(Arc::from("fuzz.acf"), &text);
    }
}
