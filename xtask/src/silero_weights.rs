//! `cargo xtask silero-weights [--check]`: regenerates `assets/models/silero_vad_v6_16k.bin`
//! (the Silero VAD v6 16 kHz weights embedded in `pneuma-core`) bit for bit from the ONNX model
//! `silero_vad_op18_ifless.onnx` of the PyPI package `silero-vad` at [`PACKAGE`], installed
//! without dependencies into the virtual environment [`VENV`] (created when missing; pip checks
//! the wheel's SHA-256). The ONNX file is read here with a small protobuf reader (top-level graph
//! initializers only): no Python package beyond pip is needed. `--check` compares instead of
//! writing and fails on any difference.

use std::path::{Path, PathBuf};

use std::process::Command;

use pneuma_core::speech::weights::{SileroWeights, TENSORS};

/// The pinned package: name, version and the SHA-256 of its wheel.
pub const PACKAGE: &str = "silero-vad==6.2.3 \
--hash=sha256:7b7f5436cfcb02fae583a05b512ea96467fd449fe54cb49a5e4f06c51a1e43b8";
/// The virtual environment (under the workspace root), shared with `pneuma eval podcast`'s
/// Silero baseline.
pub const VENV: &str = "target/venv-speech";
/// The model file inside the installed package.
const ONNX_IN_PACKAGE: &str = "silero_vad/data/silero_vad_op18_ifless.onnx";
/// Where the weights go, under the workspace root.
const OUTPUT: &str = "assets/models/silero_vad_v6_16k.bin";

/// Runs the chore; returns the process exit code.
pub fn main(args: &[String]) -> i32 {
    let mut check = false;
    for a in args {
        match a.as_str() {
            "--check" => check = true,
            other => {
                eprintln!("error: unknown argument `{other}` (use --check)");
                return 2;
            }
        }
    }
    match run(check) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("silero-weights: {e}");
            1
        }
    }
}

fn run(check: bool) -> Result<i32, String> {
    let root = crate::workspace_root();
    let onnx_path = installed_onnx(&root.join(VENV))?;
    let onnx = std::fs::read(&onnx_path).map_err(|e| format!("{}: {e}", onnx_path.display()))?;
    let weights = weights_from_onnx(&onnx)?;
    let bytes = weights
        .to_bytes()
        .ok_or("a tensor does not have its shape's number of values")?;
    // The same checks the library makes on the embedded copy (except the digest, which a new
    // file may change).
    SileroWeights::parse_unchecked(&bytes).map_err(|e| e.to_string())?;
    let out = root.join(OUTPUT);
    println!(
        "{} tensors, {} bytes, FNV-1a {:016x} (from {})",
        TENSORS.len(),
        bytes.len(),
        pneuma_core::speech::weights::fnv1a64(&bytes),
        onnx_path.display()
    );
    if check {
        let committed = std::fs::read(&out).map_err(|e| format!("{}: {e}", out.display()))?;
        if committed != bytes {
            eprintln!(
                "{OUTPUT} differs from the weights regenerated from {}: run `cargo xtask silero-weights` and commit the file",
                PACKAGE.split_whitespace().next().unwrap_or(PACKAGE)
            );
            return Ok(1);
        }
        println!("{OUTPUT} is reproduced bit for bit");
        return Ok(0);
    }
    std::fs::write(&out, &bytes).map_err(|e| format!("{}: {e}", out.display()))?;
    println!("wrote {OUTPUT}");
    Ok(0)
}

/// Path of the ONNX model in the venv, installing the pinned package first when needed.
fn installed_onnx(venv: &Path) -> Result<PathBuf, String> {
    let python = venv.join("bin/python");
    if !python.exists() {
        let status = Command::new("python3")
            .args(["-m", "venv"])
            .arg(venv)
            .status()
            .map_err(|e| format!("cannot run python3 to make {}: {e}", venv.display()))?;
        if !status.success() {
            return Err(format!(
                "python3 -m venv {} failed: install python3-venv (Debian) and retry",
                venv.display()
            ));
        }
    }
    let out = Command::new(&python)
        .args([
            "-c",
            "import sysconfig; print(sysconfig.get_paths()['purelib'])",
        ])
        .output()
        .map_err(|e| format!("{}: {e}", python.display()))?;
    let site = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    let onnx = site.join(ONNX_IN_PACKAGE);
    let version_ok = std::fs::read_dir(&site)
        .map(|d| {
            d.flatten()
                .any(|e| e.file_name() == "silero_vad-6.2.3.dist-info")
        })
        .unwrap_or(false);
    if onnx.exists() && version_ok {
        return Ok(onnx);
    }
    let requirements = venv.join("silero-requirements.txt");
    std::fs::write(&requirements, format!("{PACKAGE}\n"))
        .map_err(|e| format!("{}: {e}", requirements.display()))?;
    let status = Command::new(venv.join("bin/pip"))
        .args(["install", "--quiet", "--no-deps", "--require-hashes", "-r"])
        .arg(&requirements)
        .status()
        .map_err(|e| format!("cannot run pip in {}: {e}", venv.display()))?;
    if !status.success() || !onnx.exists() {
        return Err(format!(
            "pip could not install {PACKAGE} into {} (network to PyPI needed once)",
            venv.display()
        ));
    }
    Ok(onnx)
}

/// The network's tensors from an ONNX model's top-level initializers, in [`TENSORS`] order.
pub fn weights_from_onnx(onnx: &[u8]) -> Result<SileroWeights, String> {
    let graph = fields(onnx)?
        .into_iter()
        .find(|f| f.number == 7)
        .and_then(|f| f.bytes)
        .ok_or("the ONNX file has no graph")?;
    let mut found: Vec<Option<Vec<f32>>> = vec![None; TENSORS.len()];
    for init in fields(graph)?.into_iter().filter(|f| f.number == 5) {
        let t = tensor(init.bytes.ok_or("an initializer is not a message")?)?;
        let Some(k) = TENSORS.iter().position(|(n, _)| *n == t.name) else {
            continue;
        };
        let (name, shape) = TENSORS[k];
        if !t.float {
            return Err(format!(
                "{name} is not a tensor of 32-bit floats in the ONNX file"
            ));
        }
        if t.dims != shape {
            return Err(format!(
                "{name} has shape {:?} in the ONNX file, expected {shape:?}",
                t.dims
            ));
        }
        found[k] = Some(t.values);
    }
    let tensors = found
        .into_iter()
        .zip(TENSORS)
        .map(|(v, (name, _))| v.ok_or(format!("the ONNX file has no initializer {name}")))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(SileroWeights { tensors })
}

/// One protobuf field: its number and, for length-delimited fields, its bytes (else its
/// varint or fixed value).
struct Field<'a> {
    number: u64,
    value: u64,
    bytes: Option<&'a [u8]>,
}

/// The fields of a protobuf message, in order.
fn fields(mut msg: &[u8]) -> Result<Vec<Field<'_>>, String> {
    let mut out = Vec::new();
    while !msg.is_empty() {
        let key = varint(&mut msg)?;
        let (number, wire) = (key >> 3, key & 7);
        let field = match wire {
            0 => Field {
                number,
                value: varint(&mut msg)?,
                bytes: None,
            },
            1 | 5 => {
                let n = if wire == 1 { 8 } else { 4 };
                let b = split(&mut msg, n)?;
                let mut v = [0u8; 8];
                v[..n].copy_from_slice(b);
                Field {
                    number,
                    value: u64::from_le_bytes(v),
                    bytes: None,
                }
            }
            2 => {
                let n = varint(&mut msg)? as usize;
                Field {
                    number,
                    value: 0,
                    bytes: Some(split(&mut msg, n)?),
                }
            }
            other => return Err(format!("protobuf wire type {other} is not supported")),
        };
        out.push(field);
    }
    Ok(out)
}

fn split<'a>(msg: &mut &'a [u8], n: usize) -> Result<&'a [u8], String> {
    if msg.len() < n {
        return Err("the ONNX file is cut short".into());
    }
    let (a, b) = msg.split_at(n);
    *msg = b;
    Ok(a)
}

fn varint(msg: &mut &[u8]) -> Result<u64, String> {
    let mut v = 0u64;
    for shift in (0..64).step_by(7) {
        let b = *split(msg, 1)?.first().ok_or("empty")?;
        v |= u64::from(b & 0x7f) << shift;
        if b & 0x80 == 0 {
            return Ok(v);
        }
    }
    Err("a protobuf varint is too long".into())
}

/// An ONNX TensorProto of 32-bit floats.
struct Tensor {
    name: String,
    dims: Vec<usize>,
    values: Vec<f32>,
    /// The data type is 32-bit float (else `values` is empty).
    float: bool,
}

/// ONNX's data type code of 32-bit floats.
const ONNX_FLOAT: u64 = 1;

fn tensor(msg: &[u8]) -> Result<Tensor, String> {
    let (mut name, mut dims, mut data_type) = (String::new(), Vec::new(), 0);
    let (mut raw, mut floats) = (None, Vec::new());
    for f in fields(msg)? {
        match (f.number, f.bytes) {
            (1, None) => dims.push(f.value as usize),
            (1, Some(mut packed)) => {
                while !packed.is_empty() {
                    dims.push(varint(&mut packed)? as usize);
                }
            }
            (2, _) => data_type = f.value,
            (4, None) => floats.push(f32::from_bits(f.value as u32)),
            (4, Some(packed)) => floats.extend(
                packed
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            ),
            (8, Some(b)) => name = String::from_utf8_lossy(b).into_owned(),
            (9, Some(b)) => raw = Some(b),
            _ => {}
        }
    }
    let values = match raw {
        Some(b) => b
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect(),
        None => floats,
    };
    if data_type != ONNX_FLOAT {
        // Other initializers (shapes, indices): the network's tensors are all floats.
        return Ok(Tensor {
            name,
            dims,
            values: Vec::new(),
            float: false,
        });
    }
    if values.len() != dims.iter().product::<usize>() {
        return Err(format!(
            "initializer {name}: {} values for shape {dims:?}",
            values.len()
        ));
    }
    Ok(Tensor {
        name,
        dims,
        values,
        float: true,
    })
}
