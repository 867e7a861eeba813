//! `modelDescription.xml` of the FMU, FMI 3.0 or 2.0: the plant's inputs and outputs (each a
//! VARIABLE, named as in the dataset), its parameters and `initial_static`, with the value
//! references of [`Layout`].
//!
//! Both versions declare: co-simulation only, a variable communication step, inputs held
//! over a step (no interpolation: FMI 2.0's `canInterpolateInputs="false"`, FMI 3.0 no
//! input derivatives), get/set FMU state supported and serialisation not
//! (`canSerializeFMUState="false"`). A VARIABLE carries no unit in an Adams dataset, so the
//! ports have none; the dataset's UNITS are in the model's description.

use crate::config::{Config, Layout};
use linkage_api::cosim::Ports;
use std::collections::HashSet;
use std::fmt::Write;

/// The FMI version of an FMU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmiVersion {
    V2,
    V3,
}

impl FmiVersion {
    /// The folder of the platform binary in the FMU (`binaries/<this>/`).
    pub fn platform_folder(self) -> &'static str {
        match self {
            FmiVersion::V2 => "linux64",
            FmiVersion::V3 => "x86_64-linux",
        }
    }
}

/// What the description says about the model besides its variables.
pub struct About<'a> {
    pub model_name: &'a str,
    pub model_identifier: &'a str,
    /// The dataset's title and units.
    pub description: &'a str,
    /// `linkage <version>`.
    pub generation_tool: &'a str,
}

/// The variables' names: the dataset's, made unique (a repeated name gets its VARIABLE id).
pub struct Names {
    pub inputs: Vec<String>,
    pub outputs: Vec<String>,
    pub parameters: Vec<String>,
}

/// The name of the Boolean parameter that asks for a static equilibrium before the first step.
pub const INITIAL_STATIC: &str = "initial_static";

impl Names {
    pub fn new(ports: &Ports, config: &Config) -> Names {
        let mut taken: HashSet<String> = ["time", INITIAL_STATIC].map(String::from).into();
        let mut unique = |name: String, id: u32| {
            let name = if taken.contains(&name) {
                format!("{name} (VARIABLE/{id})")
            } else {
                name
            };
            taken.insert(name.clone());
            name
        };
        let inputs = ports
            .inputs
            .iter()
            .map(|p| unique(p.name.clone(), p.id))
            .collect();
        let outputs = ports
            .outputs
            .iter()
            .map(|p| unique(p.name.clone(), p.id))
            .collect();
        Names {
            inputs,
            outputs,
            parameters: config.parameters.iter().map(|p| p.name()).collect(),
        }
    }
}

/// `s` with the five XML special characters escaped (attribute values).
fn xml(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// A real number as XML Schema's `double` (round-trip exact).
fn real(x: f64) -> String {
    if x.is_finite() {
        format!("{x:?}")
    } else if x.is_nan() {
        "NaN".into()
    } else if x > 0.0 {
        "INF".into()
    } else {
        "-INF".into()
    }
}

/// The model description of `version`.
pub fn model_description(
    version: FmiVersion,
    about: &About,
    ports: &Ports,
    config: &Config,
) -> String {
    match version {
        FmiVersion::V3 => fmi3(about, ports, config),
        FmiVersion::V2 => fmi2(about, ports, config),
    }
}

fn fmi3(about: &About, ports: &Ports, config: &Config) -> String {
    let layout = Layout::new(ports, config);
    let names = Names::new(ports, config);
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" instantiationToken="{}" description="{}" generationTool="{}" variableNamingConvention="flat">"#,
        xml(about.model_name),
        xml(&config.token),
        xml(about.description),
        xml(about.generation_tool)
    );
    let _ = writeln!(
        s,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canGetAndSetFMUState="true" canSerializeFMUState="false" canReturnEarlyAfterIntermediateUpdate="false" hasEventMode="false" providesIntermediateUpdate="false"/>"#,
        xml(about.model_identifier)
    );
    let _ = writeln!(s, "  <ModelVariables>");
    let _ = writeln!(
        s,
        r#"    <Float64 name="time" valueReference="0" causality="independent" variability="continuous" description="simulation time"/>"#
    );
    for (k, p) in ports.inputs.iter().enumerate() {
        let _ = writeln!(
            s,
            r#"    <Float64 name="{}" valueReference="{}" causality="input" variability="continuous" start="{}" description="VARIABLE/{}, plant input"/>"#,
            xml(&names.inputs[k]),
            layout.input(k),
            real(p.start),
            p.id
        );
    }
    for (k, p) in ports.outputs.iter().enumerate() {
        let _ = writeln!(
            s,
            r#"    <Float64 name="{}" valueReference="{}" causality="output" variability="continuous" initial="calculated" description="VARIABLE/{}, plant output"/>"#,
            xml(&names.outputs[k]),
            layout.output(k),
            p.id
        );
    }
    for (k, p) in config.parameters.iter().enumerate() {
        let _ = writeln!(
            s,
            r#"    <Float64 name="{}" valueReference="{}" causality="parameter" variability="fixed" initial="exact" start="{}" description="argument {} of {}"/>"#,
            xml(&names.parameters[k]),
            layout.parameter(k),
            real(p.start),
            xml(&p.argument),
            xml(&p.statement)
        );
    }
    let _ = writeln!(
        s,
        r#"    <Boolean name="{INITIAL_STATIC}" valueReference="{}" causality="parameter" variability="fixed" initial="exact" start="{}" description="find the static equilibrium (as the dataset's EQUILIBRIUM says) before the first step"/>"#,
        layout.initial_static(),
        config.initial_static
    );
    let _ = writeln!(s, "  </ModelVariables>");
    let _ = writeln!(s, "  <ModelStructure>");
    for k in 0..layout.outputs {
        let _ = writeln!(s, r#"    <Output valueReference="{}"/>"#, layout.output(k));
    }
    for k in 0..layout.outputs {
        let _ = writeln!(
            s,
            r#"    <InitialUnknown valueReference="{}"/>"#,
            layout.output(k)
        );
    }
    let _ = writeln!(s, "  </ModelStructure>");
    let _ = writeln!(s, "</fmiModelDescription>");
    s
}

fn fmi2(about: &About, ports: &Ports, config: &Config) -> String {
    let layout = Layout::new(ports, config);
    let names = Names::new(ports, config);
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="{}" generationTool="{}" variableNamingConvention="flat" numberOfEventIndicators="0">"#,
        xml(about.model_name),
        xml(&config.token),
        xml(about.description),
        xml(about.generation_tool)
    );
    let _ = writeln!(
        s,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" canGetAndSetFMUstate="true" canSerializeFMUstate="false" canNotUseMemoryManagementFunctions="true"/>"#,
        xml(about.model_identifier)
    );
    let _ = writeln!(s, "  <ModelVariables>");
    // FMI 2.0 names a variable in the model structure by its 1-based place in this list.
    let mut index = 0usize;
    let mut output_index = Vec::new();
    for (k, p) in ports.inputs.iter().enumerate() {
        index += 1;
        let _ = writeln!(
            s,
            r#"    <ScalarVariable name="{}" valueReference="{}" causality="input" variability="continuous" description="VARIABLE/{}, plant input"><Real start="{}"/></ScalarVariable>"#,
            xml(&names.inputs[k]),
            layout.input(k),
            p.id,
            real(p.start)
        );
    }
    for (k, p) in ports.outputs.iter().enumerate() {
        index += 1;
        output_index.push(index);
        let _ = writeln!(
            s,
            r#"    <ScalarVariable name="{}" valueReference="{}" causality="output" variability="continuous" initial="calculated" description="VARIABLE/{}, plant output"><Real/></ScalarVariable>"#,
            xml(&names.outputs[k]),
            layout.output(k),
            p.id
        );
    }
    for (k, p) in config.parameters.iter().enumerate() {
        let _ = writeln!(
            s,
            r#"    <ScalarVariable name="{}" valueReference="{}" causality="parameter" variability="fixed" initial="exact" description="argument {} of {}"><Real start="{}"/></ScalarVariable>"#,
            xml(&names.parameters[k]),
            layout.parameter(k),
            xml(&p.argument),
            xml(&p.statement),
            real(p.start)
        );
    }
    let _ = writeln!(
        s,
        r#"    <ScalarVariable name="{INITIAL_STATIC}" valueReference="{}" causality="parameter" variability="fixed" initial="exact" description="find the static equilibrium (as the dataset's EQUILIBRIUM says) before the first step"><Boolean start="{}"/></ScalarVariable>"#,
        layout.initial_static(),
        config.initial_static
    );
    let _ = writeln!(s, "  </ModelVariables>");
    let _ = writeln!(s, "  <ModelStructure>");
    if !output_index.is_empty() {
        let _ = writeln!(s, "    <Outputs>");
        for i in &output_index {
            let _ = writeln!(s, r#"      <Unknown index="{i}"/>"#);
        }
        let _ = writeln!(s, "    </Outputs>");
        let _ = writeln!(s, "    <InitialUnknowns>");
        for i in &output_index {
            let _ = writeln!(s, r#"      <Unknown index="{i}"/>"#);
        }
        let _ = writeln!(s, "    </InitialUnknowns>");
    }
    let _ = writeln!(s, "  </ModelStructure>");
    let _ = writeln!(s, "</fmiModelDescription>");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use linkage_api::cosim::Port;

    fn ports() -> Ports {
        let port = |id, name: &str| Port {
            id,
            name: name.into(),
            start: 0.5,
        };
        Ports {
            pinput: Some(1),
            poutput: Some(2),
            inputs: vec![port(1, "force<N>")],
            outputs: vec![port(2, "z"), port(3, "z")],
        }
    }

    fn config() -> Config {
        Config {
            dataset: "p.adm".into(),
            pinput: None,
            poutput: None,
            parameters: vec![crate::config::Parameter {
                statement: "SPRINGDAMPER/1".into(),
                argument: "K".into(),
                start: 800.0,
            }],
            initial_static: false,
            token: "{0}".into(),
        }
    }

    const ABOUT: About = About {
        model_name: "p",
        model_identifier: "p",
        description: "d",
        generation_tool: "linkage",
    };

    #[test]
    fn a_repeated_output_name_gets_its_variable_id() {
        let n = Names::new(&ports(), &config());
        assert_eq!(n.outputs, ["z", "z (VARIABLE/3)"]);
        assert_eq!(n.parameters, ["SPRINGDAMPER/1.K"]);
    }

    #[test]
    fn fmi3_description_lists_time_inputs_outputs_and_parameters_by_value_reference() {
        let d = model_description(FmiVersion::V3, &ABOUT, &ports(), &config());
        assert!(d.contains(r#"name="time" valueReference="0" causality="independent""#));
        assert!(d.contains(r#"name="force&lt;N&gt;" valueReference="1" causality="input""#));
        assert!(d.contains(r#"valueReference="3" causality="output""#));
        assert!(d.contains(r#"name="SPRINGDAMPER/1.K" valueReference="4""#));
        assert!(d.contains(r#"<Boolean name="initial_static" valueReference="5""#));
        assert!(d.contains(r#"<Output valueReference="2"/>"#));
    }

    #[test]
    fn fmi2_model_structure_names_outputs_by_their_place_in_the_list() {
        let d = model_description(FmiVersion::V2, &ABOUT, &ports(), &config());
        assert!(d.contains(r#"<Unknown index="2"/>"#));
        assert!(d.contains(r#"<Unknown index="3"/>"#));
        assert!(!d.contains(r#"<Unknown index="1"/>"#));
        assert!(d.contains(r#"guid="{0}""#));
    }
}
