//! Reading gmsh MSH 4.1 files (ASCII or binary) into a [`Mesh`]: nodes and cells through the
//! `mshio` crate, physical groups from the entities' physical tags, and their names from the
//! `$PhysicalNames` section, which `mshio` does not parse.

use std::collections::HashMap;
use std::path::Path;

use super::{CellBlock, CellKind, Group, Mesh};
use crate::error::MeshError;

/// The file as `mshio` returns it (node tags `u64`, entity tags `i32`, coordinates `f64`).
type MshFile = mshio::MshFile<u64, i32, f64>;

/// An element block of a type rubsim does not read: (type, cell count, entity dimension,
/// entity tag).
type Unsupported = (String, usize, i32, i32);

impl Mesh {
    /// Reads an MSH 4.1 file (ASCII or binary).
    pub fn read(path: &Path) -> Result<Mesh, MeshError> {
        let bytes = std::fs::read(path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                MeshError::MissingFile {
                    file: path.to_path_buf(),
                    referenced_by: None,
                }
            } else {
                MeshError::Io {
                    file: path.to_path_buf(),
                    source: e,
                }
            }
        })?;
        Self::parse(path, &bytes)
    }

    /// Parses the bytes of an MSH 4.1 file; `path` is used in messages only.
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Mesh, MeshError> {
        let parse_err = |message: String| MeshError::Parse {
            file: path.to_path_buf(),
            message,
        };
        let numbers = check_version(bytes).map_err(parse_err)?;
        check_section_counts(bytes, numbers).map_err(parse_err)?;
        let msh = parse_with_mshio(bytes).map_err(parse_err)?;
        let names = physical_names(bytes).map_err(parse_err)?;
        let (nodes, node_tags) = read_nodes(&msh).map_err(parse_err)?;
        let index: HashMap<u64, usize> =
            node_tags.iter().enumerate().map(|(i, &t)| (t, i)).collect();
        if index.len() != node_tags.len() {
            return Err(parse_err("duplicate node tags".into()));
        }
        let (blocks, unsupported) = read_cells(&msh, &index).map_err(parse_err)?;
        let groups = read_groups(&msh, &names);
        let mesh = Mesh {
            file: path.to_path_buf(),
            nodes,
            node_tags,
            blocks,
            groups,
        };
        if let Some((kind, count, dim, entity)) = unsupported {
            let group = mesh
                .groups
                .iter()
                .find(|g| g.dim as i32 == dim && g.entities.contains(&entity))
                .map_or_else(
                    || format!("(entity {entity} of dimension {dim})"),
                    |g| g.name.clone(),
                );
            return Err(MeshError::UnsupportedCell {
                file: path.to_path_buf(),
                group,
                kind,
                count,
            });
        }
        Ok(mesh)
    }
}

/// How the numbers after the `$MeshFormat` header are written, as `mshio` reads them: text, or
/// binary in the byte order given by the test value `1` (an `int`) that follows the format line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Numbers {
    /// ASCII file: integers as decimal digits between whitespace.
    Text,
    /// Binary file: `size_t` as 8 bytes, big-endian when `true`.
    Binary { big_endian: bool },
}

/// Checks the `$MeshFormat` header: an MSH file of version 4.1 with 8-byte `size_t`; how its
/// numbers are written. Done before `mshio` parses, since `mshio` reads 4.1 only, its errors on
/// 2.2 files are cryptic and it panics on other data sizes.
fn check_version(bytes: &[u8]) -> Result<Numbers, String> {
    if !bytes.starts_with(b"$MeshFormat") {
        return Err("the file does not start with $MeshFormat (not a gmsh .msh file?)".into());
    }
    let header = String::from_utf8_lossy(&bytes[..bytes.len().min(64)]);
    let line = header.lines().nth(1).unwrap_or_default();
    let fields: Vec<&str> = line.split_whitespace().collect();
    let version = fields.first().copied();
    let binary = fields.get(1) == Some(&"1");
    if version != Some("4.1") {
        return Err(format!(
            "MSH format version {}{} (rubsim reads MSH 4.1, ASCII or binary: mesh with `-format msh41`, or convert with `gmsh FILE.msh -save -format msh41 -o NEW.msh`)",
            version.unwrap_or("?"),
            if binary { ", binary" } else { "" }
        ));
    }
    // `version file-type data-size`: 0 ASCII or 1 binary, and 8-byte size_t (what gmsh writes;
    // the parser has no reader for other sizes).
    if fields.len() != 3 || !matches!(fields[1], "0" | "1") || fields[2] != "8" {
        return Err(format!(
            "line 2: the format line `{}` is not `4.1 0 8` (ASCII) or `4.1 1 8` (binary)",
            line.trim()
        ));
    }
    if !binary {
        return Ok(Numbers::Text);
    }
    // The test value follows the format line's end (its second `\n`), as `mshio` reads it:
    // big-endian when it reads 1 that way, else little-endian when it reads 1 so.
    let test = bytes
        .iter()
        .enumerate()
        .filter(|(_, &b)| b == b'\n')
        .nth(1)
        .and_then(|(i, _)| bytes.get(i + 1..i + 5))
        .and_then(|t| <[u8; 4]>::try_from(t).ok());
    match test {
        Some(t) if i32::from_be_bytes(t) == 1 => Ok(Numbers::Binary { big_endian: true }),
        Some(t) if i32::from_le_bytes(t) == 1 => Ok(Numbers::Binary { big_endian: false }),
        _ => Err(
            "line 3: binary file without the byte-order test value 1 after the format line".into(),
        ),
    }
}

/// Checks the counts that open every `$Nodes` and `$Elements` section (`numEntityBlocks
/// numEntries minTag maxTag`): at least one entry and `minTag ≤ maxTag`. `mshio` computes
/// `numEntries − 1` unchecked (an overflow panic with overflow checks, a wrapped value and a
/// wrong reading without them; found by fuzzing). Every place `mshio` could take for the start of
/// such a section is checked — each occurrence of the section's name followed by a line end,
/// whatever precedes it (a section may follow another on the same line, sit after a CRLF, be
/// repeated or be preceded by the same bytes inside another section) — with the counts read the
/// way `mshio` reads them (text, or 8-byte integers in the file's byte order). Counts that do
/// not read are left to `mshio`, which stops there with an error.
fn check_section_counts(bytes: &[u8], numbers: Numbers) -> Result<(), String> {
    for (section, what) in [("$Nodes", "nodes"), ("$Elements", "elements")] {
        let mut from = 0;
        while let Some(at) = find(&bytes[from..], section.as_bytes()).map(|i| i + from) {
            from = at + section.len();
            let rest = &bytes[from..];
            let body = if rest.starts_with(b"\n") {
                &rest[1..]
            } else if rest.starts_with(b"\r\n") {
                &rest[2..]
            } else {
                continue;
            };
            let Some([_, n, lo, hi]) = section_counts(body, numbers) else {
                continue;
            };
            let place = match numbers {
                Numbers::Text => format!(
                    "line {}",
                    bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1
                ),
                Numbers::Binary { .. } => format!("byte {at}"),
            };
            if n == 0 {
                return Err(format!("{section} ({place}) declares 0 {what}"));
            }
            if lo > hi {
                return Err(format!(
                    "{section} ({place}): smallest tag {lo} above the largest {hi}"
                ));
            }
        }
    }
    Ok(())
}

/// The four counts opening a `$Nodes` or `$Elements` section, read from `body` (the bytes after
/// the section's line end) the way `mshio` reads `size_t` values, or `None` where it cannot.
fn section_counts(body: &[u8], numbers: Numbers) -> Option<[u64; 4]> {
    let mut v = [0u64; 4];
    match numbers {
        Numbers::Binary { big_endian } => {
            for (x, c) in v.iter_mut().zip(body.chunks_exact(8)) {
                let c: [u8; 8] = c.try_into().ok()?;
                *x = if big_endian {
                    u64::from_be_bytes(c)
                } else {
                    u64::from_le_bytes(c)
                };
            }
            (body.len() >= 32).then_some(v)
        }
        Numbers::Text => {
            // `mshio`: whitespace (space, tab, CR, LF), one or more digits, whitespace.
            let space = |b: &u8| b" \t\r\n".contains(b);
            let mut rest = body;
            for x in &mut v {
                let start = rest.iter().position(|b| !space(b))?;
                rest = &rest[start..];
                let len = rest
                    .iter()
                    .position(|b| !b.is_ascii_digit())
                    .unwrap_or(rest.len());
                *x = std::str::from_utf8(&rest[..len]).ok()?.parse().ok()?;
                rest = &rest[len..];
            }
            Some(v)
        }
    }
}

/// The file through `mshio`. The input is checked before for what `mshio` is known to panic on
/// (the header, [`check_version`]; the section counts, [`check_section_counts`]); a panic that
/// remains is caught and reported as an error rather than taking the program down (the fuzz
/// target `msh`, whose panic hook aborts, still finds them).
fn parse_with_mshio(bytes: &[u8]) -> Result<MshFile, String> {
    match std::panic::catch_unwind(|| {
        mshio::parse_msh_bytes(bytes).map_err(|e| mshio_message(bytes, &e))
    }) {
        Ok(r) => r,
        Err(p) => Err(format!(
            "the MSH parser failed on this file ({})",
            p.downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| p.downcast_ref::<&str>().copied())
                .unwrap_or("no message")
        )),
    }
}

/// A `mshio` parse error as `line N: what: why` (outermost context first).
fn mshio_message(bytes: &[u8], e: &mshio::MshParserError<&[u8]>) -> String {
    let bt = e.filtered_backtrace();
    let line = bt.first().map(|(rest, _)| {
        let off = bytes.len() - rest.len();
        bytes[..off].iter().filter(|b| **b == b'\n').count() + 1
    });
    let what: Vec<String> = bt.iter().rev().map(|(_, k)| k.to_string()).collect();
    format!(
        "{}{}",
        line.map(|l| format!("line {l}: ")).unwrap_or_default(),
        what.join(": ")
    )
}

/// Node coordinates and gmsh tags, in file order. A dense numbering (no tags stored) counts up
/// from the section's smallest tag; one that would pass 2⁶⁴ − 1 is an error.
fn read_nodes(msh: &MshFile) -> Result<(Vec<[f64; 3]>, Vec<u64>), String> {
    let mut nodes = Vec::new();
    let mut node_tags = Vec::new();
    if let Some(nd) = &msh.data.nodes {
        let mut next_tag = nd.min_node_tag;
        let past = |tag: u64, n: usize| {
            tag.checked_add(n as u64).ok_or_else(|| {
                format!("$Nodes: {n} nodes numbered from {tag} pass the largest tag 2^64 - 1")
            })
        };
        for b in &nd.node_blocks {
            let mut tags: Vec<u64> = match &b.node_tags {
                Some(map) => {
                    let mut t = vec![0; b.nodes.len()];
                    for (tag, &i) in map {
                        t[i] = *tag;
                    }
                    t
                }
                // Dense numbering: gmsh writes the tags of a dense file in block order.
                None => {
                    past(next_tag, b.nodes.len())?;
                    (0..b.nodes.len() as u64).map(|i| next_tag + i).collect()
                }
            };
            next_tag = past(next_tag, b.nodes.len())?;
            for n in &b.nodes {
                nodes.push([n.x, n.y, n.z]);
            }
            node_tags.append(&mut tags);
        }
    }
    Ok((nodes, node_tags))
}

/// The cell blocks of the types rubsim reads, connectivity mapped to node indices through
/// `index` (gmsh node tag → index), and the first block of another type, if any.
fn read_cells(
    msh: &MshFile,
    index: &HashMap<u64, usize>,
) -> Result<(Vec<CellBlock>, Option<Unsupported>), String> {
    let mut blocks: Vec<CellBlock> = Vec::new();
    let mut unsupported: Option<Unsupported> = None;
    if let Some(el) = &msh.data.elements {
        for b in &el.element_blocks {
            let Some(kind) = CellKind::from_gmsh(b.element_type) else {
                unsupported.get_or_insert((
                    format!("{:?}", b.element_type),
                    b.elements.len(),
                    b.entity_dim,
                    b.entity_tag,
                ));
                continue;
            };
            let mut conn = Vec::with_capacity(b.elements.len() * kind.nodes());
            let mut tags = Vec::with_capacity(b.elements.len());
            for e in &b.elements {
                if e.nodes.len() != kind.nodes() {
                    return Err(format!(
                        "element {} has {} nodes, a {} has {}",
                        e.element_tag,
                        e.nodes.len(),
                        kind.name(),
                        kind.nodes()
                    ));
                }
                for t in &e.nodes {
                    let i = index.get(t).ok_or_else(|| {
                        format!(
                            "element {} refers to node {t}, which is not in $Nodes",
                            e.element_tag
                        )
                    })?;
                    conn.push(*i);
                }
                tags.push(e.element_tag);
            }
            blocks.push(CellBlock {
                kind,
                entity_dim: b.entity_dim.max(0) as usize,
                entity: b.entity_tag,
                conn,
                tags,
            });
        }
    }
    Ok((blocks, unsupported))
}

/// The physical groups: entities carry their physical tags; `names` are the `(dim, tag, name)`
/// of `$PhysicalNames` (a group without a name is called `group_<tag>`).
fn read_groups(msh: &MshFile, names: &[(usize, i32, String)]) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    if let Some(ent) = &msh.data.entities {
        let mut add = |dim: usize, etag: i32, phys: &[i32]| {
            for &p in phys {
                let p = p.abs();
                match groups.iter_mut().find(|g| g.dim == dim && g.tag == p) {
                    Some(g) => g.entities.push(etag),
                    None => groups.push(Group {
                        name: names
                            .iter()
                            .find(|(d, t, _)| *d == dim && *t == p)
                            .map(|(_, _, n)| n.clone())
                            .unwrap_or_else(|| format!("group_{p}")),
                        dim,
                        tag: p,
                        entities: vec![etag],
                    }),
                }
            }
        };
        for e in &ent.points {
            add(0, e.tag, &e.physical_tags);
        }
        for e in &ent.curves {
            add(1, e.tag, &e.physical_tags);
        }
        for e in &ent.surfaces {
            add(2, e.tag, &e.physical_tags);
        }
        for e in &ent.volumes {
            add(3, e.tag, &e.physical_tags);
        }
    }
    // Named groups without entities (possible in hand-written files) still get listed.
    for (d, t, n) in names {
        if !groups.iter().any(|g| g.dim == *d && g.tag == *t) {
            groups.push(Group {
                name: n.clone(),
                dim: *d,
                tag: *t,
                entities: vec![],
            });
        }
    }
    groups
}

/// Parses the `$PhysicalNames` section (ASCII even in binary files): `(dim, tag, name)`.
fn physical_names(bytes: &[u8]) -> Result<Vec<(usize, i32, String)>, String> {
    let start = match find(bytes, b"$PhysicalNames") {
        Some(s) => s + b"$PhysicalNames".len(),
        None => return Ok(vec![]),
    };
    let end = find(&bytes[start..], b"$EndPhysicalNames")
        .ok_or("$PhysicalNames without $EndPhysicalNames")?
        + start;
    let text = std::str::from_utf8(&bytes[start..end])
        .map_err(|_| "$PhysicalNames is not UTF-8 text".to_string())?;
    let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    let n: usize = lines
        .next()
        .and_then(|l| l.parse().ok())
        .ok_or("$PhysicalNames: missing count")?;
    let mut out = Vec::with_capacity(n);
    for l in lines.take(n) {
        let mut it = l.splitn(3, char::is_whitespace);
        let bad = || format!("$PhysicalNames: cannot read `{l}`");
        let dim: usize = it.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let tag: i32 = it.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let name = it
            .next()
            .ok_or_else(bad)?
            .trim()
            .trim_matches('"')
            .to_string();
        out.push((dim, tag, name));
    }
    if out.len() != n {
        return Err(format!(
            "$PhysicalNames announces {n} names, holds {}",
            out.len()
        ));
    }
    Ok(out)
}

/// Byte offset of the first occurrence of `needle` in `hay`.
fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_other_formats_with_the_file_name() {
        let e = Mesh::parse(
            Path::new("old.msh"),
            b"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("old.msh") && e.contains("2.2"), "{e}");
        // Found by fuzzing: a data size other than 8 made the parser panic.
        let e = Mesh::parse(
            Path::new("odd.msh"),
            b"$MeshFormat\n4.1 1 9\n\x01\0\0\0\n$EndMeshFormat\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("odd.msh") && e.contains("`4.1 1 9`"), "{e}");
        // Found by fuzzing: a smallest node tag above the largest (mshio subtracts them).
        let e = Mesh::parse(
            Path::new("tags.msh"),
            b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 5 1\n$EndNodes\n",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("tags.msh") && e.contains("$Nodes (line 4): smallest tag 5"),
            "{e}"
        );
        let e = Mesh::parse(Path::new("x.msh"), b"hello")
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.msh"), "{e}");
    }

    /// A binary header with the byte-order test value written `order`, then `body`.
    fn binary(big_endian: bool, body: &[u8]) -> Vec<u8> {
        let one = if big_endian {
            1i32.to_be_bytes()
        } else {
            1i32.to_le_bytes()
        };
        let mut b = b"$MeshFormat\n4.1 1 8\n".to_vec();
        b.extend(one);
        b.extend(b"\n$EndMeshFormat\n");
        b.extend(body);
        b
    }

    #[test]
    fn section_counts_are_read_in_the_files_byte_order() {
        let counts = |v: [u64; 4], big: bool| -> Vec<u8> {
            v.iter()
                .flat_map(|x| {
                    if big {
                        x.to_be_bytes()
                    } else {
                        x.to_le_bytes()
                    }
                })
                .collect()
        };
        for big in [false, true] {
            let file = binary(big, b"");
            let numbers = check_version(&file).unwrap();
            assert_eq!(numbers, Numbers::Binary { big_endian: big });
            let body = counts([1, 0, 1, 1], big);
            assert_eq!(section_counts(&body, numbers), Some([1, 0, 1, 1]));
            let mut file = binary(big, b"$Nodes\n");
            file.extend(&body);
            let e = check_section_counts(&file, numbers).unwrap_err();
            assert_eq!(e, "$Nodes (byte 40) declares 0 nodes");
            // Too short to hold the counts: left to mshio.
            assert_eq!(section_counts(&body[..31], numbers), None);
        }
        // Neither byte order reads the test value as 1.
        let mut file = binary(false, b"");
        file[20..24].copy_from_slice(&2i32.to_le_bytes());
        assert!(check_version(&file).unwrap_err().contains("byte-order"));
    }

    #[test]
    fn text_counts_are_read_like_mshio_reads_them() {
        let n = Numbers::Text;
        assert_eq!(section_counts(b" 1\r\n2\t3 4\n", n), Some([1, 2, 3, 4]));
        assert_eq!(section_counts(b"1 2 3", n), None);
        assert_eq!(section_counts(b"1 2 3 x", n), None);
        assert_eq!(section_counts(b"1 2 3 99999999999999999999", n), None);
        // A name not followed by a line end is no section start; one after a section's end
        // on the same line is.
        let ok = b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodesx\n1 0 1 1\n";
        assert!(check_section_counts(ok, n).is_ok());
        let bad = b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$EndEntities$Elements\r\n1 0 1 1\n";
        let e = check_section_counts(bad, n).unwrap_err();
        assert_eq!(e, "$Elements (line 4) declares 0 elements");
    }
}
