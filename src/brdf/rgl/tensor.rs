//! The tensor file container of the RGL material database (Dupuy & Jakob 2018), as the
//! readers of Mitsuba 3 (`TensorFile`) and pbrt-v4 (`Tensor`) read it.
//!
//! # Layout (all integers little-endian)
//! - 12 bytes: the magic `tensor_file` and a NUL;
//! - 2 bytes: version, major then minor: `1, 0`;
//! - `u32`: the number of fields;
//! - per field: `u16` name length, the name (bytes), `u16` rank, `u8` dtype, `u64` byte
//!   offset of the data from the start of the file, then `rank` x `u64` shape;
//! - the data of each field at its offset: `product(shape)` values of the dtype,
//!   little-endian, row-major (last index fastest).
//!
//! dtype codes (Mitsuba's `Struct::Type`): 1 `u8`, 2 `i8`, 3 `u16`, 4 `i16`, 5 `u32`, 6 `i32`,
//! 7 `u64`, 8 `i64`, 9 `f16`, 10 `f32`, 11 `f64`.
//!
//! The parser borrows the data from the file's bytes and allocates nothing sized by the
//! file's claims: every name, rank, shape and offset is checked against the bytes that
//! are there (with overflow-checked arithmetic) before it is used.

/// Magic bytes at the start of a tensor file.
pub const MAGIC: &[u8; 12] = b"tensor_file\0";
/// The version this parser reads (major, minor).
pub const VERSION: [u8; 2] = [1, 0];
/// Most fields a file may declare (an RGL material has ten).
pub const MAX_FIELDS: u32 = 64;
/// Longest field name, bytes.
pub const MAX_NAME: usize = 256;
/// Highest rank (the RGL `spectra` field has 5).
pub const MAX_RANK: usize = 8;

/// A field's element type (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    U64,
    I64,
    F16,
    F32,
    F64,
}

impl Dtype {
    /// The dtype of a file code, `None` for an unknown code.
    pub fn from_code(c: u8) -> Option<Dtype> {
        use Dtype::*;
        Some(match c {
            1 => U8,
            2 => I8,
            3 => U16,
            4 => I16,
            5 => U32,
            6 => I32,
            7 => U64,
            8 => I64,
            9 => F16,
            10 => F32,
            11 => F64,
            _ => return None,
        })
    }

    /// The file code.
    pub fn code(self) -> u8 {
        use Dtype::*;
        match self {
            U8 => 1,
            I8 => 2,
            U16 => 3,
            I16 => 4,
            U32 => 5,
            I32 => 6,
            U64 => 7,
            I64 => 8,
            F16 => 9,
            F32 => 10,
            F64 => 11,
        }
    }

    /// Bytes per element.
    pub fn size(self) -> u64 {
        use Dtype::*;
        match self {
            U8 | I8 => 1,
            U16 | I16 | F16 => 2,
            U32 | I32 | F32 => 4,
            U64 | I64 | F64 => 8,
        }
    }

    /// The name used in messages (`float32`, `uint8`, ...).
    pub fn name(self) -> &'static str {
        use Dtype::*;
        match self {
            U8 => "uint8",
            I8 => "int8",
            U16 => "uint16",
            I16 => "int16",
            U32 => "uint32",
            I32 => "int32",
            U64 => "uint64",
            I64 => "int64",
            F16 => "float16",
            F32 => "float32",
            F64 => "float64",
        }
    }
}

/// One field of a tensor file, its data borrowed from the file's bytes.
#[derive(Clone, Debug)]
pub struct Field<'a> {
    pub name: String,
    pub dtype: Dtype,
    pub shape: Vec<u64>,
    pub offset: u64,
    /// Exactly `product(shape) * dtype.size()` bytes.
    pub data: &'a [u8],
}

/// What is wrong with a tensor file: `field` names the field (or the header part), and
/// `problem` says what; the caller adds the file's path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TensorError {
    pub field: String,
    pub problem: String,
}

fn err(field: impl Into<String>, problem: impl Into<String>) -> TensorError {
    TensorError {
        field: field.into(),
        problem: problem.into(),
    }
}

/// A cursor over the header that refuses to read past the end.
struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str, field: &str) -> Result<&'a [u8], TensorError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len());
        match end {
            Some(e) => {
                let s = &self.bytes[self.pos..e];
                self.pos = e;
                Ok(s)
            }
            None => Err(err(
                field,
                format!(
                    "the file ends at byte {} inside the field header (its {what})",
                    self.bytes.len()
                ),
            )),
        }
    }
    fn u8(&mut self, what: &str, field: &str) -> Result<u8, TensorError> {
        Ok(self.take(1, what, field)?[0])
    }
    fn u16(&mut self, what: &str, field: &str) -> Result<u16, TensorError> {
        Ok(u16::from_le_bytes(
            self.take(2, what, field)?.try_into().unwrap(),
        ))
    }
    fn u64(&mut self, what: &str, field: &str) -> Result<u64, TensorError> {
        Ok(u64::from_le_bytes(
            self.take(8, what, field)?.try_into().unwrap(),
        ))
    }
}

/// Parses a tensor file's header and locates each field's data (module doc). Fails on a
/// short file, a wrong magic or version, more than [`MAX_FIELDS`] fields, a name that is
/// empty, too long, not UTF-8 or repeated, an unknown dtype, a rank over [`MAX_RANK`], or
/// data that does not lie inside the file.
pub fn parse(bytes: &[u8]) -> Result<Vec<Field<'_>>, TensorError> {
    if bytes.len() < 18 {
        return Err(err(
            "header",
            format!(
                "file is {} bytes, shorter than the 18-byte tensor file header (truncated?)",
                bytes.len()
            ),
        ));
    }
    if &bytes[..12] != MAGIC {
        return Err(err(
            "header",
            format!(
                "not a tensor file: starts with {:?}, expected \"tensor_file\\0\"",
                String::from_utf8_lossy(&bytes[..12])
            ),
        ));
    }
    if bytes[12..14] != VERSION {
        return Err(err(
            "header",
            format!(
                "tensor file version {}.{}, this reader knows 1.0",
                bytes[12], bytes[13]
            ),
        ));
    }
    let n = u32::from_le_bytes(bytes[14..18].try_into().unwrap());
    if n > MAX_FIELDS {
        return Err(err(
            "header",
            format!("declares {n} fields, more than the {MAX_FIELDS} a material file may have"),
        ));
    }
    let mut r = Reader { bytes, pos: 18 };
    let len = bytes.len() as u64;
    let mut fields: Vec<Field> = Vec::with_capacity(n as usize);
    for k in 0..n {
        let label = format!("field #{k}");
        let name_len = r.u16("name length", &label)? as usize;
        if name_len == 0 || name_len > MAX_NAME {
            return Err(err(
                label,
                format!("name length {name_len}, expected 1 to {MAX_NAME} bytes"),
            ));
        }
        let name = std::str::from_utf8(r.take(name_len, "name", &label)?)
            .map_err(|_| err(&label, "name is not UTF-8"))?
            .to_string();
        if fields.iter().any(|f| f.name == name) {
            return Err(err(name, "appears twice in the file"));
        }
        let rank = r.u16("rank", &name)? as usize;
        if rank > MAX_RANK {
            return Err(err(
                name,
                format!("rank {rank}, more than the {MAX_RANK} this reader accepts"),
            ));
        }
        let code = r.u8("dtype", &name)?;
        let dtype = Dtype::from_code(code)
            .ok_or_else(|| err(&name, format!("unknown dtype code {code} (known: 1 to 11)")))?;
        let offset = r.u64("offset", &name)?;
        let mut shape = Vec::with_capacity(rank);
        for _ in 0..rank {
            shape.push(r.u64("shape", &name)?);
        }
        let bytes_needed = shape
            .iter()
            .try_fold(dtype.size(), |acc, &d| acc.checked_mul(d));
        let end = bytes_needed.and_then(|b| offset.checked_add(b).map(|e| (b, e)));
        let end = match end {
            Some((_, e)) if e <= len => e,
            _ => {
                return Err(err(
                    name,
                    format!(
                        "shape {shape:?} of {} at offset {offset} does not fit in the \
                         {len}-byte file (truncated, or a corrupt shape or offset)",
                        dtype.name()
                    ),
                ))
            }
        };
        fields.push(Field {
            name,
            dtype,
            shape,
            offset,
            data: &bytes[offset as usize..end as usize],
        });
    }
    Ok(fields)
}

/// The bytes of a tensor file holding `fields` (name, dtype, shape, little-endian data),
/// data laid out after the header in the order given, each at an 8-byte aligned offset.
/// Panics if a field's data length disagrees with its shape (a writer's bug).
pub fn write(fields: &[(&str, Dtype, Vec<u64>, Vec<u8>)]) -> Vec<u8> {
    let mut header = Vec::new();
    header.extend_from_slice(MAGIC);
    header.extend_from_slice(&VERSION);
    header.extend_from_slice(&(fields.len() as u32).to_le_bytes());
    let header_len: usize = 18
        + fields
            .iter()
            .map(|(n, _, s, _)| 2 + n.len() + 2 + 1 + 8 + 8 * s.len())
            .sum::<usize>();
    let align = |x: usize| x.div_ceil(8) * 8;
    let mut offset = align(header_len);
    let mut offsets = Vec::new();
    for (name, dtype, shape, data) in fields {
        let n: u64 = shape.iter().product();
        assert_eq!(data.len() as u64, n * dtype.size(), "field {name}");
        header.extend_from_slice(&(name.len() as u16).to_le_bytes());
        header.extend_from_slice(name.as_bytes());
        header.extend_from_slice(&(shape.len() as u16).to_le_bytes());
        header.push(dtype.code());
        header.extend_from_slice(&(offset as u64).to_le_bytes());
        for d in shape {
            header.extend_from_slice(&d.to_le_bytes());
        }
        offsets.push(offset);
        offset = align(offset + data.len());
    }
    debug_assert_eq!(header.len(), header_len);
    let mut out = header;
    for ((_, _, _, data), off) in fields.iter().zip(offsets) {
        out.resize(off, 0);
        out.extend_from_slice(data);
    }
    out
}
