//! The HDF5 building blocks every writer of this module shares: [`Column`] (a dataset that
//! grows by frames, buffered and appended in blocks), attributes, datasets written at once, and
//! the file descriptor marked close-on-exec. The time series ([`super::hdf5`], its spin columns
//! in `hdf5_spin`) and the mode shapes ([`super::mode_hdf5`]) write through them.

use h5::types::VarLenUnicode;
use h5::H5Type;
use hdf5_metno as h5;
use ndarray::{ArrayView, IxDyn};

/// Bytes buffered per dataset before a block is appended.
const BLOCK_BYTES: usize = 256 * 1024;

/// A dataset growing along its first axis by `frame_rows` rows per frame.
pub(super) struct Column<T: H5Type + Copy> {
    ds: h5::Dataset,
    frame_rows: usize,
    inner: Vec<usize>,
    frame_len: usize,
    block_frames: usize,
    buf: Vec<T>,
    buffered: usize,
    rows: usize,
}

impl<T: H5Type + Copy> Column<T> {
    /// The dataset `name` in `g`: `frame_rows` rows of shape `inner` per frame, chunked by
    /// blocks of about [`BLOCK_BYTES`], with its `unit` attribute unless empty.
    pub(super) fn new(
        g: &h5::Group,
        name: &str,
        frame_rows: usize,
        inner: &[usize],
        unit: &str,
    ) -> h5::Result<Self> {
        let frame_len = frame_rows * inner.iter().product::<usize>();
        let block_frames =
            (BLOCK_BYTES / (frame_len.max(1) * std::mem::size_of::<T>())).clamp(1, 4096);
        let mut shape: Vec<h5::Extent> = vec![h5::Extent::resizable(0)];
        shape.extend(inner.iter().map(|n| h5::Extent::fixed(*n)));
        let mut chunk = vec![(block_frames * frame_rows).max(1)];
        chunk.extend(inner.iter().map(|n| (*n).max(1)));
        let ds = g
            .new_dataset::<T>()
            .chunk(chunk)
            .shape(shape)
            .create(name)?;
        if !unit.is_empty() {
            attr_str(&ds, "unit", unit)?;
        }
        Ok(Self {
            ds,
            frame_rows,
            inner: inner.to_vec(),
            frame_len,
            block_frames,
            buf: Vec::with_capacity(block_frames * frame_len),
            buffered: 0,
            rows: 0,
        })
    }

    /// Appends one frame (`frame_len` values, row-major).
    pub(super) fn push(&mut self, v: impl IntoIterator<Item = T>) -> h5::Result<()> {
        let n0 = self.buf.len();
        self.buf.extend(v);
        debug_assert_eq!(self.buf.len() - n0, self.frame_len, "frame size");
        self.buffered += 1;
        if self.buffered >= self.block_frames {
            self.flush()?;
        }
        Ok(())
    }

    /// The first value still buffered (of the oldest frame not yet appended).
    pub(super) fn first_buffered(&self) -> Option<T> {
        self.buf.first().copied()
    }

    /// The number of frames buffered, not yet appended.
    pub(super) fn buffered_frames(&self) -> usize {
        self.buffered
    }

    /// Appends the buffered frames to the dataset.
    pub(super) fn flush(&mut self) -> h5::Result<()> {
        if self.buffered == 0 {
            return Ok(());
        }
        let n = self.buffered * self.frame_rows;
        let mut shape = vec![self.rows + n];
        shape.extend(&self.inner);
        self.ds.resize(shape)?;
        let mut vshape = vec![n];
        vshape.extend(&self.inner);
        let view = ArrayView::from_shape(IxDyn(&vshape), &self.buf)
            .map_err(|e| h5::Error::from(e.to_string().as_str()))?;
        let sel: Vec<h5::SliceOrIndex> =
            std::iter::once(h5::SliceOrIndex::from(self.rows..self.rows + n))
                .chain(self.inner.iter().map(|_| h5::SliceOrIndex::from(..)))
                .collect();
        self.ds.write_slice(view, h5::Hyperslab::from(sel))?;
        self.rows += n;
        self.buf.clear();
        self.buffered = 0;
        Ok(())
    }
}

/// Writes the string attribute `name` = `v` on `loc`.
pub(super) fn attr_str(loc: &h5::Location, name: &str, v: &str) -> h5::Result<()> {
    let s: VarLenUnicode = v
        .parse()
        .map_err(|e: h5::types::StringError| h5::Error::from(e.to_string().as_str()))?;
    loc.new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&s)
}

/// VTKHDF format version written.
pub const VTKHDF_VERSION: [i64; 2] = [2, 2];

/// The group `/VTKHDF` of `f` with its `Version` ([`VTKHDF_VERSION`]) and `Type`
/// (`UnstructuredGrid`) attributes: what every VTKHDF file starts with.
pub(super) fn vtkhdf_group(f: &h5::File) -> h5::Result<h5::Group> {
    let v = f.create_group("VTKHDF")?;
    v.new_attr_builder()
        .with_data(&VTKHDF_VERSION[..])
        .create("Version")?;
    let ty = h5::types::FixedAscii::<16>::from_ascii("UnstructuredGrid")
        .map_err(|e| h5::Error::from(e.to_string().as_str()))?;
    attr(&v, "Type", ty)?;
    Ok(v)
}

/// Writes the scalar attribute `name` = `v` on `loc`.
pub(super) fn attr<T: H5Type>(loc: &h5::Location, name: &str, v: T) -> h5::Result<()> {
    loc.new_attr::<T>().create(name)?.write_scalar(&v)
}

/// Writes the dataset `name` of `shape` (row-major `data`) at once, with its `unit` attribute
/// unless empty.
pub(super) fn static_ds<T: H5Type>(
    g: &h5::Group,
    name: &str,
    shape: &[usize],
    data: &[T],
    unit: &str,
) -> h5::Result<h5::Dataset> {
    let view = ArrayView::from_shape(IxDyn(shape), data)
        .map_err(|e| h5::Error::from(e.to_string().as_str()))?;
    let ds = g.new_dataset_builder().with_data(view).create(name)?;
    if !unit.is_empty() {
        attr_str(&ds, "unit", unit)?;
    }
    Ok(ds)
}

/// Marks the HDF5 file's descriptor close-on-exec. libhdf5 opens files without `O_CLOEXEC`
/// and holds an `flock` on them, so a process spawned while the file is being written (a
/// mesher, another rubsim) would inherit the descriptor and keep the lock after this run
/// closes the file: readers then fail with "unable to lock file". Best effort: a driver
/// without a POSIX descriptor is left alone.
pub(super) fn close_on_exec(f: &h5::File) {
    let mut handle: *mut std::ffi::c_void = std::ptr::null_mut();
    // SAFETY: `f.id()` is a valid open file id; H5P_DEFAULT selects the default (sec2) driver,
    // whose handle is a pointer to the `int` descriptor, valid while the file is open.
    let fd = h5::sync::sync(|| unsafe {
        let rc = hdf5_metno_sys::h5f::H5Fget_vfd_handle(
            f.id(),
            hdf5_metno_sys::h5p::H5P_DEFAULT,
            &mut handle,
        );
        if rc < 0 || handle.is_null() {
            None
        } else {
            Some(*(handle as *const std::ffi::c_int))
        }
    });
    if let Some(fd) = fd {
        // SAFETY: fcntl on a descriptor this process owns; only the FD_CLOEXEC flag changes.
        unsafe {
            let flags = libc::fcntl(fd, libc::F_GETFD);
            if flags >= 0 {
                libc::fcntl(fd, libc::F_SETFD, flags | libc::FD_CLOEXEC);
            }
        }
    }
}
