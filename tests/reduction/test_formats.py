import dataclasses
import filecmp

import numpy as np
import pytest
from reduction_helpers import STEEL

from flexarm.fe import ReadError
from flexarm.reduction import formats
from flexarm.reduction.formats import h5, npz
from flexarm.reduction.reduce import reduce_part
from flexarm.reduction.superelement import FORMAT_VERSION, to_arrays


@pytest.fixture(scope="module")
def se(bar):
    mesh, regions, KM = bar
    return reduce_part(mesh, STEEL, regions, "rbe3", "cb", 5, matrices=KM)


def assert_same(a, b, full: bool):
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if not full and f.name in ("T", "surface_points", "surface_faces", "surface_nodes"):
            assert y is None
            continue
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and np.array_equal(x, y), f.name
        else:
            assert x == y, f.name


@pytest.mark.parametrize("ext,full", [("h5", True), ("npz", True), ("mtx", False),
                                      ("bdf", False)])
def test_round_trip_exact(se, tmp_path, ext, full):
    path = formats.write(tmp_path / f"part.{ext}", se)
    assert_same(se, formats.read(path), full)


def test_hdf5_byte_identical(bar, tmp_path):
    mesh, regions, KM = bar
    a = formats.write(tmp_path / "a.h5", reduce_part(mesh, STEEL, regions, "rbe2", "cb", 4,
                                                     matrices=KM))
    b = formats.write(tmp_path / "b.h5", reduce_part(mesh, STEEL, regions, "rbe2", "cb", 4,
                                                     matrices=KM))
    assert filecmp.cmp(a, b, shallow=False)


def test_dmig_read_by_pynastran(se, tmp_path):
    bdf = pytest.importorskip("pyNastran.bdf.bdf")
    path = formats.write(tmp_path / "part.bdf", se)
    model = bdf.BDF(debug=None)
    model.read_bdf(str(path), xref=False, punch=True)
    ids, comps = formats.dmig.dof_labels(len(se.node_positions), se.dofs_per_node, se.n_modes)
    ours = {(int(i), int(c)): k for k, (i, c) in enumerate(zip(ids, comps, strict=True))}
    for name, ref in (("KAAX", se.K), ("MAAX", se.M)):
        A, rows, cols = model.dmig[name].get_matrix(is_sparse=False, apply_symmetry=True)
        r = [ours[tuple(rows[k])] for k in range(len(rows))]
        c = [ours[tuple(cols[k])] for k in range(len(cols))]
        assert np.abs(A - ref[np.ix_(r, c)]).max() <= 1e-12 * np.abs(ref).max()
        assert len(r) == se.n_dofs
    assert np.allclose(model.nodes[2].xyz, se.node_positions[1], rtol=0, atol=0)
    assert sorted(model.spoints) == list(range(1001, 1001 + se.n_modes))


# ------------------------------------------------------------------ bad files
def write_npz(path, d):
    np.savez(path, **{k: np.asarray(v) for k, v in d.items()})
    return path


def test_wrong_version(se, tmp_path):
    d = to_arrays(se)
    d["version"] = FORMAT_VERSION + 1
    p = write_npz(tmp_path / "v.npz", d)
    with pytest.raises(ReadError, match=r"v.npz: superelement format version 2 is not supported"):
        formats.read(p)


def test_no_version_and_missing_field(se, tmp_path):
    d = to_arrays(se)
    del d["version"]
    with pytest.raises(ReadError, match=r"nv.npz: not a flexarm superelement \(no format"):
        formats.read(write_npz(tmp_path / "nv.npz", d))
    d = to_arrays(se)
    del d["freq_hz"]
    with pytest.raises(ReadError, match=r"mf.npz: missing field\(s\) freq_hz"):
        formats.read(write_npz(tmp_path / "mf.npz", d))


def test_bad_shapes(se, tmp_path):
    d = to_arrays(se)
    d["M"] = d["M"][:-1]
    with pytest.raises(ReadError, match=r"s.npz: K and M must be square and of equal shape"):
        formats.read(write_npz(tmp_path / "s.npz", d))
    d = to_arrays(se)
    d["freq_hz"] = d["freq_hz"][:-1]
    with pytest.raises(ReadError, match=r"f.npz: 12 boundary DOFs \+ 4 modes do not match"):
        formats.read(write_npz(tmp_path / "f.npz", d))
    d = to_arrays(se)
    d["inertia"] = np.zeros(3)
    with pytest.raises(ReadError, match=r"i.npz: inertia must have shape \(3, 3\)"):
        formats.read(write_npz(tmp_path / "i.npz", d))
    d = to_arrays(se)
    d["T"] = d["T"][:, :-1]
    with pytest.raises(ReadError, match=r"t.npz: recovery matrix T must have 17 columns"):
        formats.read(write_npz(tmp_path / "t.npz", d))


def test_asymmetric_and_indefinite(se, tmp_path):
    d = to_arrays(se)
    K = d["K"].copy()
    K[0, 1] *= 1.01
    d["K"] = K
    with pytest.raises(ReadError, match=r"a.npz: K is not symmetric"):
        formats.read(write_npz(tmp_path / "a.npz", d))
    d = to_arrays(se)
    d["K"] = d["K"] - 2 * np.abs(d["K"]).max() * np.eye(se.n_dofs)
    with pytest.raises(ReadError, match=r"n.npz: K is not positive semi-definite"):
        formats.read(write_npz(tmp_path / "n.npz", d))


def test_not_our_files(tmp_path):
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"not hdf5")
    with pytest.raises(ReadError, match=r"junk.h5: not an HDF5 file"):
        h5.read(junk)
    import h5py

    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = 1
    with pytest.raises(ReadError, match=r"other.h5: not a flexarm superelement"):
        formats.read(tmp_path / "other.h5")
    (tmp_path / "junk.npz").write_bytes(b"nope")
    with pytest.raises(ReadError, match=r"junk.npz: not a NumPy .npz file"):
        npz.read(tmp_path / "junk.npz")
    (tmp_path / "x.mtx").mkdir()
    with pytest.raises(ReadError, match=r"x.mtx: not a Matrix Market superelement folder"):
        formats.read(tmp_path / "x.mtx")
    (tmp_path / "x.bdf").write_text("GRID,1,,0.,0.,0.\n")
    with pytest.raises(ReadError, match=r"x.bdf: no '\$flexarm-json' line"):
        formats.read(tmp_path / "x.bdf")
    with pytest.raises(FileNotFoundError):
        formats.read(tmp_path / "absent.h5")
    with pytest.raises(ValueError, match=r"unknown superelement extension '.xyz'"):
        formats.read(junk.rename(tmp_path / "junk.xyz"))


def test_bad_dmig_card(se, tmp_path):
    p = formats.write(tmp_path / "p.bdf", se)
    text = p.read_text().replace("DMIG,KAAX,1,1,,", "DMIG,KAAX,99,1,,", 1)
    p.write_text(text)
    with pytest.raises(ReadError, match=r"p.bdf:\d+: bad DMIG card 'DMIG,KAAX,99,1"):
        formats.read(p)


def test_unknown_extension(se, tmp_path):
    with pytest.raises(ValueError, match=r"unknown superelement extension '.xyz'"):
        formats.write(tmp_path / "a.xyz", se)
    with pytest.raises(ValueError, match="format must be one of"):
        formats.write(tmp_path / "a.h5", se, "xyz")


# ------------------------------------------------------------------ checksums
def _flip_k_bit(path, K: np.ndarray) -> None:
    """Flip the lowest mantissa bit of one K entry where the file stores it in binary."""
    raw = bytearray(path.read_bytes())
    at = raw.find(np.ascontiguousarray(K).tobytes())
    assert at >= 0, "K is not stored contiguously"
    raw[at + 8 * 7] ^= 0x01  # entry 7, least significant byte (little endian)
    path.write_bytes(bytes(raw))


def _stored_checksum(path, ext):
    import json
    import zipfile

    if ext == "h5":
        import h5py

        with h5py.File(path, "r") as f:
            return f.attrs["checksum"]
    if ext == "npz":
        with zipfile.ZipFile(path) as z:
            return z.comment.decode().split()[-1]
    if ext == "mtx":
        return json.loads((path / "superelement.json").read_text())["checksum"]
    line = next(ln for ln in path.read_text().splitlines() if ln.startswith("$flexarm-json "))
    return json.loads(line[len("$flexarm-json "):])["checksum"]


@pytest.mark.parametrize("ext", ["h5", "npz", "mtx", "bdf"])
def test_checksum_is_metadata_of_the_content_read_back(se, tmp_path, ext):
    """Each format stores the SHA-256 of exactly what a reader gets back, in its own
    metadata place, readable by the format's usual tools."""
    from flexarm.reduction.formats._checksum import content_checksum

    path = formats.write(tmp_path / f"part.{ext}", se)
    stored = _stored_checksum(path, ext)
    back = to_arrays(formats.read(path))
    assert stored.startswith("sha256:") and len(stored) == 7 + 64
    assert stored == content_checksum(back)
    if ext == "npz":  # numpy and any zip tool still read the members
        with np.load(path) as z:
            assert np.array_equal(z["K"], se.K)


@pytest.mark.parametrize("ext", ["h5", "npz"])
def test_bit_flip_in_stored_k_is_refused(se, tmp_path, ext):
    path = formats.write(tmp_path / f"part.{ext}", se)
    if ext == "npz":
        # flipping the member's bytes trips the zip CRC first; rewrite the member
        # consistently instead (a valid zip with the old comment), as an edit would
        import zipfile

        with zipfile.ZipFile(path) as z:
            comment, members = z.comment, {n: z.read(n) for n in z.namelist()}
        K = se.K.copy()
        K.ravel()[7] = np.nextafter(K.ravel()[7], np.inf)
        import io

        buf = io.BytesIO()
        np.save(buf, K)
        members["K.npy"] = buf.getvalue()
        with zipfile.ZipFile(path, "w") as z:
            for n, b in members.items():
                z.writestr(n, b)
            z.comment = comment
    else:
        _flip_k_bit(path, se.K)
    with pytest.raises(ReadError, match=rf"part.{ext}: checksum mismatch: the content is "
                                        "not what was written"):
        formats.read(path)


@pytest.mark.parametrize("ext", ["mtx", "bdf"])
def test_edited_text_value_is_refused(se, tmp_path, ext):
    """One digit of one stiffness entry changed: a valid file, not what was written."""
    path = formats.write(tmp_path / f"part.{ext}", se)
    target = path / "K.mtx" if ext == "mtx" else path
    lines = target.read_text().splitlines()
    if ext == "mtx":
        k = 3  # the first value after the header, size line
        head, value = "", lines[k]
    else:
        k = next(i for i, ln in enumerate(lines) if ln.startswith("DMIG,KAAX,1,1,,"))
        head, value = lines[k].rsplit(",", 1)[0] + ",", lines[k].rsplit(",", 1)[1]
    digit = next(i for i, c in enumerate(value) if c.isdigit() and i > 2)
    lines[k] = head + value[:digit] + str((int(value[digit]) + 1) % 10) + value[digit + 1:]
    target.write_text("\n".join(lines) + "\n")
    with pytest.raises(ReadError, match=rf"part.{ext}: checksum mismatch"):
        formats.read(path)


@pytest.mark.parametrize("ext", ["h5", "npz", "mtx", "bdf"])
def test_files_without_a_checksum_still_read(se, tmp_path, ext):
    """Files written before checksums existed (or by hand) are read as before."""
    import json
    import zipfile

    path = formats.write(tmp_path / f"old.{ext}", se)
    if ext == "h5":
        import h5py

        with h5py.File(path, "r+") as f:
            del f.attrs["checksum"]
    elif ext == "npz":
        with zipfile.ZipFile(path, "a") as z:
            z.comment = b""
    else:
        meta = path / "superelement.json" if ext == "mtx" else path
        lines = meta.read_text().splitlines()
        for k, ln in enumerate(lines):
            head = "" if ext == "mtx" else "$flexarm-json "
            if ln.startswith(head + "{"):
                d = json.loads(ln[len(head):])
                del d["checksum"]
                lines[k] = head + json.dumps(d, separators=(",", ":"))
        meta.write_text("\n".join(lines) + "\n")
    assert np.array_equal(formats.read(path).K, se.K)
