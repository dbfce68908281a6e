# This is a generated file! Please edit source .ksy file and use kaitai-struct-compiler to rebuild
# type: ignore

import kaitaistruct
from kaitaistruct import KaitaiStruct, KaitaiStream, BytesIO
from enum import IntEnum


if getattr(kaitaistruct, 'API_VERSION', (0, 9)) < (0, 11):
    raise Exception("Incompatible Kaitai Struct Python API: 0.11 or later is required, but you have %s" % (kaitaistruct.__version__))

class Bssrdf(KaitaiStruct):
    """A library file of bssrdf-zoo: baked BSSRDF tables (one per model and relative index of
    refraction η), the materials rendered with them and how they were made. This description
    follows format-spec.md, which is normative; where the two differ, the spec wins and this
    file has a bug. It describes major version 1, minors 0 to 6, and reads files of newer
    minors as far as the spec lets an older reader (unknown section kinds as bytes, the first
    64 or 512 bytes of longer records).
    
    Layout: a 128-byte header, a directory of `section_count` 64-byte entries, then the
    sections, each at the `offset` its entry gives, in directory order, with zero padding up to
    the next multiple of `alignment` before each. Every number is little-endian. The body of a
    section is reached through its entry (`directory[i].body`).
    
    What this description checks (`valid`, `contents`): the magic, the major version, the
    byte-order mark, `file_size` against the real size, and the values a single field of the
    header, of a directory entry or of a record may take on its own (alignment, dtype, codec,
    ndim, model, a walk's component and g, a table's ridge, fresnel, η, table dimensions,
    string lengths, material coefficients). A section whose `dims` ask for more bytes than it
    stores fails to parse.
    
    What it does not check, and a conforming reader must (format-spec.md sections 4 to 14):
    the CRC-32 values (`header_crc`, each entry's `crc32`) are described, not verified; nor the
    feature bits, reserved bytes and bits (whose rule depends on the minor), `raw_len` and
    `stored_len`, the placement of sections (alignment, order, overlap, gaps, padding, trailing
    data), section ownership and uniqueness, required sections, the values in the table
    sections (finite, axes in range and increasing, the node rules, the radial CDF never
    decreasing), the rules of materials that involve more than one field or record (table
    indices, unique names, σ′t > 0, the
    albedo range against its flag), control characters and the provenance JSON. `name`,
    `source` and the provenance are decoded as UTF-8 by the target language's runtime
    (Python's rejects invalid UTF-8; other targets may not).
    
    Compressed sections (codec 1, zstd) are described as their stored bytes: Kaitai Struct has
    no zstd processor built in. Decode `body` (one or more zstd frames, `raw_len` bytes once
    decoded) and parse the result with `section_body(kind, dims)` to read it like an
    uncompressed section.
    
    .. seealso::
       format-spec.md
    """

    class Codec(IntEnum):
        none = 0
        zstd = 1

    class Dtype(IntEnum):
        u8 = 1
        f32 = 2

    class Fresnel(IntEnum):
        exact = 0
        pbrt = 1

    class Model(IntEnum):
        pbd_angular = 1
        walk_angular = 3

    class SectionKind(IntEnum):
        tables = 1
        materials = 2
        provenance = 3
        axis_rho = 16
        axis_theta = 17
        axis_r = 18
        gwc_params = 32
        radial_cdf = 33
        theta_cdf = 34
        gwc_harmonics = 35

    class WalkComponent(IntEnum):
        multiple = 0
        total = 1
    def __init__(self, _io, _parent=None, _root=None):
        super(Bssrdf, self).__init__(_io)
        self._parent = _parent
        self._root = _root or self
        self._read()

    def _read(self):
        self.header = Bssrdf.Header(self._io, self, self._root)
        self.directory = []
        for i in range(self.header.section_count):
            self.directory.append(Bssrdf.DirEntry(self._io, self, self._root))



    def _fetch_instances(self):
        pass
        self.header._fetch_instances()
        for i in range(len(self.directory)):
            pass
            self.directory[i]._fetch_instances()


    class Axis(KaitaiStruct):
        """One axis of a table, strictly increasing: `axis-rho`, reduced albedo ρ′ in [0, 1];
        `axis-theta`, incidence angle θ in radians in [0, π/2]; `axis-r`, radius in reduced mean
        free paths, ≥ 0 (format-spec.md section 10).
        """
        def __init__(self, n_values, _io, _parent=None, _root=None):
            super(Bssrdf.Axis, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self.n_values = n_values
            self._read()

        def _read(self):
            self.values = []
            for i in range(self.n_values):
                self.values.append(self._io.read_f4le())



        def _fetch_instances(self):
            pass
            for i in range(len(self.values)):
                pass



    class DirEntry(KaitaiStruct):
        """One 64-byte directory entry (format-spec.md section 5)."""
        def __init__(self, _io, _parent=None, _root=None):
            super(Bssrdf.DirEntry, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self._read()

        def _read(self):
            self.kind = KaitaiStream.resolve_enum(Bssrdf.SectionKind, self._io.read_u4le())
            self.table = self._io.read_u4le()
            self.dtype = KaitaiStream.resolve_enum(Bssrdf.Dtype, self._io.read_u2le())
            if not isinstance(self.dtype, Bssrdf.Dtype):
                raise kaitaistruct.ValidationNotInEnumError(self.dtype, self._io, u"/types/dir_entry/seq/2")
            self.codec = KaitaiStream.resolve_enum(Bssrdf.Codec, self._io.read_u2le())
            if not isinstance(self.codec, Bssrdf.Codec):
                raise kaitaistruct.ValidationNotInEnumError(self.codec, self._io, u"/types/dir_entry/seq/3")
            self.flags = self._io.read_u2le()
            self.ndim = self._io.read_u2le()
            if not self.ndim >= 1:
                raise kaitaistruct.ValidationLessThanError(1, self.ndim, self._io, u"/types/dir_entry/seq/5")
            if not self.ndim <= 4:
                raise kaitaistruct.ValidationGreaterThanError(4, self.ndim, self._io, u"/types/dir_entry/seq/5")
            self.dims = []
            for i in range(4):
                self.dims.append(self._io.read_u4le())

            self.offset = self._io.read_u8le()
            self.stored_len = self._io.read_u8le()
            self.raw_len = self._io.read_u8le()
            self.crc32 = self._io.read_u4le()
            self.reserved = self._io.read_bytes(4)


        def _fetch_instances(self):
            pass
            for i in range(len(self.dims)):
                pass

            _ = self.body
            if hasattr(self, '_m_body'):
                pass
                _on = self.codec
                if _on == Bssrdf.Codec.none:
                    pass
                    self._m_body._fetch_instances()
                else:
                    pass


        @property
        def body(self):
            """The section's stored bytes. Uncompressed (codec 0), parsed by kind; compressed
            (codec 1), the zstd frames as bytes, which decode to a `section_body(kind, dims)`.
            """
            if hasattr(self, '_m_body'):
                return self._m_body

            io = self._root._io
            _pos = io.pos()
            io.seek(self.offset)
            _on = self.codec
            if _on == Bssrdf.Codec.none:
                pass
                self._raw__m_body = io.read_bytes(self.stored_len)
                _io__raw__m_body = KaitaiStream(BytesIO(self._raw__m_body))
                self._m_body = Bssrdf.SectionBody(self.kind, self.dims, _io__raw__m_body, self, self._root)
            else:
                pass
                self._m_body = io.read_bytes(self.stored_len)
            io.seek(_pos)
            return getattr(self, '_m_body', None)

        @property
        def is_file_level(self):
            """The section belongs to the file, not to a table."""
            if hasattr(self, '_m_is_file_level'):
                return self._m_is_file_level

            self._m_is_file_level = self.table == 4294967295
            return getattr(self, '_m_is_file_level', None)

        @property
        def required(self):
            """The `required` flag, bit 0 of `flags`."""
            if hasattr(self, '_m_required'):
                return self._m_required

            self._m_required = self.flags & 1 != 0
            return getattr(self, '_m_required', None)


    class GwcNode(KaitaiStruct):
        """A node of `gwc-params`: the General Wrapped Cauchy profile over the exit azimuth,
        f(φ) = α + β·pdf_WC(φ; c), stored as (E, E_β, c); β = E_β/r and α = (E − E_β)/(2πr) at
        r > 0. The node rules of format-spec.md section 10 are not checked here.
        """
        def __init__(self, _io, _parent=None, _root=None):
            super(Bssrdf.GwcNode, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self._read()

        def _read(self):
            self.e = self._io.read_f4le()
            self.e_beta = self._io.read_f4le()
            self.c = self._io.read_f4le()


        def _fetch_instances(self):
            pass


    class HarmonicsNode(KaitaiStruct):
        """A node of `gwc-harmonics` (since 1.2, required feature bit 2): the table's profile has
        two lobes, stored by its third and fourth harmonics times r, where
        μₙ = ∫ f(φ) cos nφ dφ; `gwc-params` then holds the one lobe with the same first two.
        """
        def __init__(self, _io, _parent=None, _root=None):
            super(Bssrdf.HarmonicsNode, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self._read()

        def _read(self):
            self.r_mu3 = self._io.read_f4le()
            self.r_mu4 = self._io.read_f4le()


        def _fetch_instances(self):
            pass


    class Header(KaitaiStruct):
        """The fixed 128-byte header at offset 0 (format-spec.md section 3)."""
        def __init__(self, _io, _parent=None, _root=None):
            super(Bssrdf.Header, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self._read()

        def _read(self):
            self.magic = self._io.read_bytes(12)
            if not self.magic == b"\x89\x42\x53\x53\x52\x44\x46\x0D\x0A\x1A\x0A\x00":
                raise kaitaistruct.ValidationNotEqualError(b"\x89\x42\x53\x53\x52\x44\x46\x0D\x0A\x1A\x0A\x00", self.magic, self._io, u"/types/header/seq/0")
            self.major = self._io.read_u2le()
            if not self.major == 1:
                raise kaitaistruct.ValidationNotEqualError(1, self.major, self._io, u"/types/header/seq/1")
            self.minor = self._io.read_u2le()
            self.byte_order = self._io.read_u4le()
            if not self.byte_order == 168496141:
                raise kaitaistruct.ValidationNotEqualError(168496141, self.byte_order, self._io, u"/types/header/seq/3")
            self.section_count = self._io.read_u4le()
            if not self.section_count <= 65536:
                raise kaitaistruct.ValidationGreaterThanError(65536, self.section_count, self._io, u"/types/header/seq/4")
            self.file_size = self._io.read_u8le()
            _ = self.file_size
            if not _ == self._root._io.size():
                raise kaitaistruct.ValidationExprError(self.file_size, self._io, u"/types/header/seq/5")
            self.required_features = self._io.read_u8le()
            self.optional_features = self._io.read_u8le()
            self.alignment = self._io.read_u4le()
            _ = self.alignment
            if not  ((_ >= 256) and (_ <= 65536) and (_ & _ - 1 == 0)) :
                raise kaitaistruct.ValidationExprError(self.alignment, self._io, u"/types/header/seq/8")
            self.reserved = self._io.read_bytes(72)
            self.header_crc = self._io.read_u4le()


        def _fetch_instances(self):
            pass

        @property
        def dir_end(self):
            """End of the directory, where the padding before the first section starts."""
            if hasattr(self, '_m_dir_end'):
                return self._m_dir_end

            self._m_dir_end = 128 + 64 * self.section_count
            return getattr(self, '_m_dir_end', None)

        @property
        def harmonics(self):
            """Required feature bit 2, `harmonics` (since 1.2)."""
            if hasattr(self, '_m_harmonics'):
                return self._m_harmonics

            self._m_harmonics = self.required_features & 4 != 0
            return getattr(self, '_m_harmonics', None)

        @property
        def merged_roots(self):
            """Required feature bit 4, `merged-roots` (since 1.4)."""
            if hasattr(self, '_m_merged_roots'):
                return self._m_merged_roots

            self._m_merged_roots = self.required_features & 16 != 0
            return getattr(self, '_m_merged_roots', None)

        @property
        def ridge(self):
            """Required feature bit 6, `ridge` (since 1.6)."""
            if hasattr(self, '_m_ridge'):
                return self._m_ridge

            self._m_ridge = self.required_features & 64 != 0
            return getattr(self, '_m_ridge', None)

        @property
        def signed_floor(self):
            """Required feature bit 1, `signed-floor` (since 1.1)."""
            if hasattr(self, '_m_signed_floor'):
                return self._m_signed_floor

            self._m_signed_floor = self.required_features & 2 != 0
            return getattr(self, '_m_signed_floor', None)

        @property
        def signed_lobes(self):
            """Required feature bit 3, `signed-lobes` (since 1.3)."""
            if hasattr(self, '_m_signed_lobes'):
                return self._m_signed_lobes

            self._m_signed_lobes = self.required_features & 8 != 0
            return getattr(self, '_m_signed_lobes', None)

        @property
        def walk_tables(self):
            """Required feature bit 5, `walk-tables` (since 1.5)."""
            if hasattr(self, '_m_walk_tables'):
                return self._m_walk_tables

            self._m_walk_tables = self.required_features & 32 != 0
            return getattr(self, '_m_walk_tables', None)

        @property
        def zstd_sections(self):
            """Required feature bit 0, `zstd-sections`."""
            if hasattr(self, '_m_zstd_sections'):
                return self._m_zstd_sections

            self._m_zstd_sections = self.required_features & 1 != 0
            return getattr(self, '_m_zstd_sections', None)


    class MaterialRecord(KaitaiStruct):
        """One material (format-spec.md section 9.2): a medium's coefficients per channel (R, G,
        B) and the table each channel is rendered with.
        """
        def __init__(self, _io, _parent=None, _root=None):
            super(Bssrdf.MaterialRecord, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self._read()

        def _read(self):
            self.name_len = self._io.read_u4le()
            if not self.name_len >= 1:
                raise kaitaistruct.ValidationLessThanError(1, self.name_len, self._io, u"/types/material_record/seq/0")
            if not self.name_len <= 64:
                raise kaitaistruct.ValidationGreaterThanError(64, self.name_len, self._io, u"/types/material_record/seq/0")
            self.source_len = self._io.read_u4le()
            if not self.source_len <= 256:
                raise kaitaistruct.ValidationGreaterThanError(256, self.source_len, self._io, u"/types/material_record/seq/1")
            self.table = []
            for i in range(3):
                self.table.append(self._io.read_u4le())

            self.flags = self._io.read_u4le()
            self.sigma_s = []
            for i in range(3):
                self.sigma_s.append(self._io.read_f8le())
                _ = self.sigma_s[i]
                if not  ((_ >= 0) and (_ <= 1.7976931348623157E+308)) :
                    raise kaitaistruct.ValidationExprError(self.sigma_s[i], self._io, u"/types/material_record/seq/4")

            self.sigma_a = []
            for i in range(3):
                self.sigma_a.append(self._io.read_f8le())
                _ = self.sigma_a[i]
                if not  ((_ >= 0) and (_ <= 1.7976931348623157E+308)) :
                    raise kaitaistruct.ValidationExprError(self.sigma_a[i], self._io, u"/types/material_record/seq/5")

            self.g = []
            for i in range(3):
                self.g.append(self._io.read_f8le())
                _ = self.g[i]
                if not  ((_ > -1) and (_ < 1)) :
                    raise kaitaistruct.ValidationExprError(self.g[i], self._io, u"/types/material_record/seq/6")

            self.eta = self._io.read_f8le()
            _ = self.eta
            if not  ((_ > 0) and (_ <= 1.7976931348623157E+308)) :
                raise kaitaistruct.ValidationExprError(self.eta, self._io, u"/types/material_record/seq/7")
            self.albedo_min = []
            for i in range(3):
                self.albedo_min.append(self._io.read_f8le())
                _ = self.albedo_min[i]
                if not  ((_ >= 0) and (_ <= 1)) :
                    raise kaitaistruct.ValidationExprError(self.albedo_min[i], self._io, u"/types/material_record/seq/8")

            self.albedo_max = []
            for i in range(3):
                self.albedo_max.append(self._io.read_f8le())
                _ = self.albedo_max[i]
                if not  ((_ >= 0) and (_ <= 1)) :
                    raise kaitaistruct.ValidationExprError(self.albedo_max[i], self._io, u"/types/material_record/seq/9")

            self.reserved = self._io.read_bytes(40)
            self.name = (self._io.read_bytes(self.name_len)).decode(u"UTF-8")
            self.name_unused = self._io.read_bytes(64 - self.name_len)
            self.source = (self._io.read_bytes(self.source_len)).decode(u"UTF-8")
            self.source_unused = self._io.read_bytes(256 - self.source_len)


        def _fetch_instances(self):
            pass
            for i in range(len(self.table)):
                pass

            for i in range(len(self.sigma_s)):
                pass

            for i in range(len(self.sigma_a)):
                pass

            for i in range(len(self.g)):
                pass

            for i in range(len(self.albedo_min)):
                pass

            for i in range(len(self.albedo_max)):
                pass


        @property
        def has_albedo_range(self):
            """Flag bit 0, the albedo range is meaningful."""
            if hasattr(self, '_m_has_albedo_range'):
                return self._m_has_albedo_range

            self._m_has_albedo_range = self.flags & 1 != 0
            return getattr(self, '_m_has_albedo_range', None)


    class NodeGrid(KaitaiStruct):
        """A section with one record per node (i, j, k) = (ρ′, θ, r) of the table's nρ × nθ × nr
        grid: `gwc-params` or `gwc-harmonics`. Node (i, j, k) is `nodes[(i · nθ + j) · nr + k]`
        (format-spec.md section 10).
        """
        def __init__(self, kind, n_rho, n_theta, n_r, _io, _parent=None, _root=None):
            super(Bssrdf.NodeGrid, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self.kind = kind
            self.n_rho = n_rho
            self.n_theta = n_theta
            self.n_r = n_r
            self._read()

        def _read(self):
            self.nodes = []
            for i in range((self.n_rho * self.n_theta) * self.n_r):
                _on = self.kind
                if _on == Bssrdf.SectionKind.gwc_harmonics:
                    pass
                    self.nodes.append(Bssrdf.HarmonicsNode(self._io, self, self._root))
                elif _on == Bssrdf.SectionKind.gwc_params:
                    pass
                    self.nodes.append(Bssrdf.GwcNode(self._io, self, self._root))



        def _fetch_instances(self):
            pass
            for i in range(len(self.nodes)):
                pass
                _on = self.kind
                if _on == Bssrdf.SectionKind.gwc_harmonics:
                    pass
                    self.nodes[i]._fetch_instances()
                elif _on == Bssrdf.SectionKind.gwc_params:
                    pass
                    self.nodes[i]._fetch_instances()



    class Provenance(KaitaiStruct):
        """How the file was made: one JSON object (RFC 8259) in UTF-8, at most 1 MiB, written
        canonically (format-spec.md section 11). Its keys are not described here.
        """
        def __init__(self, _io, _parent=None, _root=None):
            super(Bssrdf.Provenance, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self._read()

        def _read(self):
            self.json = (self._io.read_bytes_full()).decode(u"UTF-8")


        def _fetch_instances(self):
            pass


    class RadialCdf(KaitaiStruct):
        """For each (i, j), the running integral over r of the spline through E, 0 at the first
        radius; the last value is the effective albedo ρ_eff(ρ′_i, θ_j). Element (i, j, k) is
        `values[(i · nθ + j) · nr + k]`.
        """
        def __init__(self, n_rho, n_theta, n_r, _io, _parent=None, _root=None):
            super(Bssrdf.RadialCdf, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self.n_rho = n_rho
            self.n_theta = n_theta
            self.n_r = n_r
            self._read()

        def _read(self):
            self.values = []
            for i in range((self.n_rho * self.n_theta) * self.n_r):
                self.values.append(self._io.read_f4le())



        def _fetch_instances(self):
            pass
            for i in range(len(self.values)):
                pass



    class Records(KaitaiStruct):
        """The `tables` and `materials` sections: arrays of fixed-size records (format-spec.md
        section 9), `dims` [count, record size]. Table i is record i of `tables`, material j
        record j of `materials`. Records are 64 (tables) or 512 (materials) bytes; a file of a
        newer minor may have longer ones, whose first 64 or 512 bytes are as described and whose
        extra bytes are skipped.
        """
        def __init__(self, kind, n_records, record_size, _io, _parent=None, _root=None):
            super(Bssrdf.Records, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self.kind = kind
            self.n_records = n_records
            self.record_size = record_size
            self._read()

        def _read(self):
            self._raw_records = []
            self.records = []
            for i in range(self.n_records):
                _on = self.kind
                if _on == Bssrdf.SectionKind.materials:
                    pass
                    self._raw_records.append(self._io.read_bytes(self.record_size))
                    _io__raw_records = KaitaiStream(BytesIO(self._raw_records[i]))
                    self.records.append(Bssrdf.MaterialRecord(_io__raw_records, self, self._root))
                elif _on == Bssrdf.SectionKind.tables:
                    pass
                    self._raw_records.append(self._io.read_bytes(self.record_size))
                    _io__raw_records = KaitaiStream(BytesIO(self._raw_records[i]))
                    self.records.append(Bssrdf.TableRecord(_io__raw_records, self, self._root))
                else:
                    pass
                    self.records.append(self._io.read_bytes(self.record_size))



        def _fetch_instances(self):
            pass
            for i in range(len(self.records)):
                pass
                _on = self.kind
                if _on == Bssrdf.SectionKind.materials:
                    pass
                    self.records[i]._fetch_instances()
                elif _on == Bssrdf.SectionKind.tables:
                    pass
                    self.records[i]._fetch_instances()
                else:
                    pass



    class SectionBody(KaitaiStruct):
        """The decoded bytes of one section, by kind (format-spec.md sections 8 to 11). Usable on
        its own, e.g. on the output of a zstd decoder for a compressed section.
        """
        def __init__(self, kind, dims, _io, _parent=None, _root=None):
            super(Bssrdf.SectionBody, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self.kind = kind
            self.dims = dims
            self._read()

        def _read(self):
            _on = self.kind
            if _on == Bssrdf.SectionKind.axis_r:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.Axis(self.dims[0], _io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.axis_rho:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.Axis(self.dims[0], _io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.axis_theta:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.Axis(self.dims[0], _io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.gwc_harmonics:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.NodeGrid(self.kind, self.dims[0], self.dims[1], self.dims[2], _io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.gwc_params:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.NodeGrid(self.kind, self.dims[0], self.dims[1], self.dims[2], _io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.materials:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.Records(self.kind, self.dims[0], self.dims[1], _io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.provenance:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.Provenance(_io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.radial_cdf:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.RadialCdf(self.dims[0], self.dims[1], self.dims[2], _io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.tables:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.Records(self.kind, self.dims[0], self.dims[1], _io__raw_content, self, self._root)
            elif _on == Bssrdf.SectionKind.theta_cdf:
                pass
                self._raw_content = self._io.read_bytes_full()
                _io__raw_content = KaitaiStream(BytesIO(self._raw_content))
                self.content = Bssrdf.ThetaCdf(self.dims[0], self.dims[1], _io__raw_content, self, self._root)
            else:
                pass
                self.content = self._io.read_bytes_full()


        def _fetch_instances(self):
            pass
            _on = self.kind
            if _on == Bssrdf.SectionKind.axis_r:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.axis_rho:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.axis_theta:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.gwc_harmonics:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.gwc_params:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.materials:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.provenance:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.radial_cdf:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.tables:
                pass
                self.content._fetch_instances()
            elif _on == Bssrdf.SectionKind.theta_cdf:
                pass
                self.content._fetch_instances()
            else:
                pass


    class TableRecord(KaitaiStruct):
        """One table (format-spec.md section 9.1), in reduced units: independent of g, except a
        walk-angular table (model 3), which holds the g of its walk. Bytes 28 to 63 depend on
        the model: `ridge` then reserved bytes in a pbd-angular record, `component`, `g`,
        `ridge` then reserved bytes in a walk-angular one.
        """
        def __init__(self, _io, _parent=None, _root=None):
            super(Bssrdf.TableRecord, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self._read()

        def _read(self):
            self.model = KaitaiStream.resolve_enum(Bssrdf.Model, self._io.read_u4le())
            if not isinstance(self.model, Bssrdf.Model):
                raise kaitaistruct.ValidationNotInEnumError(self.model, self._io, u"/types/table_record/seq/0")
            self.fresnel = KaitaiStream.resolve_enum(Bssrdf.Fresnel, self._io.read_u4le())
            if not isinstance(self.fresnel, Bssrdf.Fresnel):
                raise kaitaistruct.ValidationNotInEnumError(self.fresnel, self._io, u"/types/table_record/seq/1")
            self.eta = self._io.read_f8le()
            _ = self.eta
            if not  ((_ > 0) and (_ <= 1.7976931348623157E+308)) :
                raise kaitaistruct.ValidationExprError(self.eta, self._io, u"/types/table_record/seq/2")
            self.n_rho = self._io.read_u4le()
            if not self.n_rho >= 1:
                raise kaitaistruct.ValidationLessThanError(1, self.n_rho, self._io, u"/types/table_record/seq/3")
            if not self.n_rho <= 65536:
                raise kaitaistruct.ValidationGreaterThanError(65536, self.n_rho, self._io, u"/types/table_record/seq/3")
            self.n_theta = self._io.read_u4le()
            if not self.n_theta >= 1:
                raise kaitaistruct.ValidationLessThanError(1, self.n_theta, self._io, u"/types/table_record/seq/4")
            if not self.n_theta <= 65536:
                raise kaitaistruct.ValidationGreaterThanError(65536, self.n_theta, self._io, u"/types/table_record/seq/4")
            self.n_r = self._io.read_u4le()
            if not self.n_r >= 1:
                raise kaitaistruct.ValidationLessThanError(1, self.n_r, self._io, u"/types/table_record/seq/5")
            if not self.n_r <= 65536:
                raise kaitaistruct.ValidationGreaterThanError(65536, self.n_r, self._io, u"/types/table_record/seq/5")
            if self.model == Bssrdf.Model.walk_angular:
                pass
                self.component = KaitaiStream.resolve_enum(Bssrdf.WalkComponent, self._io.read_u4le())
                if not isinstance(self.component, Bssrdf.WalkComponent):
                    raise kaitaistruct.ValidationNotInEnumError(self.component, self._io, u"/types/table_record/seq/6")

            if self.model == Bssrdf.Model.walk_angular:
                pass
                self.g = self._io.read_f8le()
                _ = self.g
                if not  ((_ > -1) and (_ < 1)) :
                    raise kaitaistruct.ValidationExprError(self.g, self._io, u"/types/table_record/seq/7")

            self.ridge = self._io.read_u4le()
            if not self.ridge <= 2:
                raise kaitaistruct.ValidationGreaterThanError(2, self.ridge, self._io, u"/types/table_record/seq/8")
            self.reserved = self._io.read_bytes((20 if self.model == Bssrdf.Model.walk_angular else 32))


        def _fetch_instances(self):
            pass
            if self.model == Bssrdf.Model.walk_angular:
                pass

            if self.model == Bssrdf.Model.walk_angular:
                pass



    class ThetaCdf(KaitaiStruct):
        """For each i, the running integral over θ of the spline through ρ_eff(ρ′_i, θ_j), 0 at
        the first angle (optional, for sampling θ). Element (i, j) is `values[i · nθ + j]`.
        """
        def __init__(self, n_rho, n_theta, _io, _parent=None, _root=None):
            super(Bssrdf.ThetaCdf, self).__init__(_io)
            self._parent = _parent
            self._root = _root
            self.n_rho = n_rho
            self.n_theta = n_theta
            self._read()

        def _read(self):
            self.values = []
            for i in range(self.n_rho * self.n_theta):
                self.values.append(self._io.read_f4le())



        def _fetch_instances(self):
            pass
            for i in range(len(self.values)):
                pass




