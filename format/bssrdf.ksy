meta:
  id: bssrdf
  title: bssrdf-zoo library file (baked BSSRDF tables), format 1.x
  application: bssrdf-zoo
  file-extension: bssrdf
  license: MIT OR Apache-2.0
  ks-version: '0.11'
  endian: le
doc: |
  A library file of bssrdf-zoo: baked BSSRDF tables (one per model and relative index of
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
doc-ref: format-spec.md
seq:
  - id: header
    type: header
  - id: directory
    type: dir_entry
    repeat: expr
    repeat-expr: header.section_count
    doc: One entry per section, in the order the sections are stored (format-spec.md section 5).
types:
  header:
    doc: The fixed 128-byte header at offset 0 (format-spec.md section 3).
    seq:
      - id: magic
        contents: [0x89, BSSRDF, 0x0d, 0x0a, 0x1a, 0x0a, 0x00]
        doc: |
          `\x89BSSRDF\r\n\x1a\n\0`: a first byte above 0x7F so that the file is never taken
          for text, CR LF, Ctrl-Z and LF so that a line-ending conversion or a transfer that
          stops at Ctrl-Z damages it visibly.
      - id: major
        type: u2
        valid: 1
        doc: |
          Format major version. Bytes 0 to 19 keep their place and meaning in every major;
          everything after them is described here for major 1 only. A file written
          big-endian fails here (its major reads 256) before its byte-order mark is read.
      - id: minor
        type: u2
        doc: |
          Format minor version: 6 for format 1.6 (0 to 5 in files of formats 1.0 to 1.5).
          Minors only add; a newer minor is read as far as this description goes.
      - id: byte_order
        type: u4
        valid: 0x0a0b0c0d
        doc: Byte-order mark, stored as `0D 0C 0B 0A`; a big-endian writer would give 0x0D0C0B0A.
      - id: section_count
        type: u4
        valid:
          max: 65536
        doc: Number of directory entries.
      - id: file_size
        type: u8
        valid:
          expr: _ == _root._io.size
        doc: Total size of the file in bytes; must equal the real size.
      - id: required_features
        type: u8
        doc: |
          Feature bits a reader must understand, or reject the file: bit 0 `zstd-sections`
          (some section has codec 1), bit 1 `signed-floor` (since 1.1: some gwc-params node
          has E_β > E), bit 2 `harmonics` (since 1.2: some table has a gwc-harmonics
          section), bit 3 `signed-lobes` (since 1.3: some gwc-harmonics node is a sharp lobe
          less a broader one), bit 4 `merged-roots` (since 1.4: the two-lobe tables rebuild a
          merged pair where Prony's roots give no lobes), bit 5 `walk-tables` (since 1.5: some
          table is walk-angular, model 3), bit 6 `ridge` (since 1.6: some table's nodes hold
          its profile less the analytic ridge, its record's `ridge` = 1 or 2). Bits 7 to 63
          are reserved for later minors. Not checked here.
      - id: optional_features
        type: u8
        doc: Feature bits a reader may ignore; none are defined in 1.0 to 1.6.
      - id: alignment
        type: u4
        valid:
          expr: _ >= 256 and _ <= 65536 and (_ & (_ - 1)) == 0
        doc: Section alignment in bytes, a power of two in [256, 65536]; writers use 256.
      - id: reserved
        size: 72
        doc: |
          Zero. A reader rejects a non-zero byte in a file of its own or an older minor and
          ignores it in a newer minor; not checked here.
      - id: header_crc
        type: u4
        doc: |
          CRC-32 (IEEE 802.3 / zlib) of bytes 0..123 of the file followed by the whole
          directory (bytes 128 .. 128 + 64 × section_count − 1). Described, not verified.
    instances:
      zstd_sections:
        value: (required_features & 1) != 0
        doc: Required feature bit 0, `zstd-sections`.
      signed_floor:
        value: (required_features & 2) != 0
        doc: Required feature bit 1, `signed-floor` (since 1.1).
      harmonics:
        value: (required_features & 4) != 0
        doc: Required feature bit 2, `harmonics` (since 1.2).
      signed_lobes:
        value: (required_features & 8) != 0
        doc: Required feature bit 3, `signed-lobes` (since 1.3).
      merged_roots:
        value: (required_features & 16) != 0
        doc: Required feature bit 4, `merged-roots` (since 1.4).
      walk_tables:
        value: (required_features & 32) != 0
        doc: Required feature bit 5, `walk-tables` (since 1.5).
      ridge:
        value: (required_features & 64) != 0
        doc: Required feature bit 6, `ridge` (since 1.6).
      dir_end:
        value: 128 + 64 * section_count
        doc: End of the directory, where the padding before the first section starts.

  dir_entry:
    doc: One 64-byte directory entry (format-spec.md section 5).
    seq:
      - id: kind
        type: u4
        enum: section_kind
        doc: |
          Section kind code (format-spec.md section 8). Codes this description does not know
          are extension kinds: their body is bytes.
      - id: table
        type: u4
        doc: Index of the table the section belongs to, or 0xFFFFFFFF for a file-level section.
      - id: dtype
        type: u2
        enum: dtype
        valid:
          in-enum: true
        doc: Element type; an unknown dtype makes the file unreadable.
      - id: codec
        type: u2
        enum: codec
        valid:
          in-enum: true
        doc: How the section is stored; an unknown codec makes the file unreadable.
      - id: flags
        type: u2
        doc: |
          Bit 0 `required`: a reader that does not know `kind` must reject the file. Bits 1
          to 15 are reserved (zero, unless the file is of a newer minor); not checked here.
      - id: ndim
        type: u2
        valid:
          min: 1
          max: 4
        doc: Number of dimensions.
      - id: dims
        type: u4
        repeat: expr
        repeat-expr: 4
        doc: |
          Dimensions, outermost first; the entries at and after `ndim` are 0. For the table
          kinds they are nρ, nθ, nr (and 3 or 2 per node); for records, [count, record size].
      - id: offset
        type: u8
        doc: Offset of the stored bytes from the start of the file, a multiple of `alignment`.
      - id: stored_len
        type: u8
        doc: Number of stored bytes; equal to `raw_len` for codec 0. Not checked here.
      - id: raw_len
        type: u8
        doc: |
          Number of bytes once decoded: the product of `dims` times the size of `dtype`.
          Not checked here.
      - id: crc32
        type: u4
        doc: CRC-32 of the `stored_len` stored bytes (compressed ones for codec 1). Not verified.
      - id: reserved
        size: 4
        doc: Zero (not checked here).
    instances:
      required:
        value: (flags & 1) != 0
        doc: The `required` flag, bit 0 of `flags`.
      is_file_level:
        value: table == 0xffffffff
        doc: The section belongs to the file, not to a table.
      body:
        io: _root._io
        pos: offset
        size: stored_len
        type:
          switch-on: codec
          cases:
            codec::none: section_body(kind, dims)
        doc: |
          The section's stored bytes. Uncompressed (codec 0), parsed by kind; compressed
          (codec 1), the zstd frames as bytes, which decode to a `section_body(kind, dims)`.

  section_body:
    doc: |
      The decoded bytes of one section, by kind (format-spec.md sections 8 to 11). Usable on
      its own, e.g. on the output of a zstd decoder for a compressed section.
    params:
      - id: kind
        type: u4
        enum: section_kind
      - id: dims
        type: u4[]
        doc: The entry's four `dims`.
    seq:
      - id: content
        size-eos: true
        type:
          switch-on: kind
          cases:
            section_kind::tables: records(kind, dims[0], dims[1])
            section_kind::materials: records(kind, dims[0], dims[1])
            section_kind::provenance: provenance
            section_kind::axis_rho: axis(dims[0])
            section_kind::axis_theta: axis(dims[0])
            section_kind::axis_r: axis(dims[0])
            section_kind::gwc_params: node_grid(kind, dims[0], dims[1], dims[2])
            section_kind::radial_cdf: radial_cdf(dims[0], dims[1], dims[2])
            section_kind::theta_cdf: theta_cdf(dims[0], dims[1])
            section_kind::gwc_harmonics: node_grid(kind, dims[0], dims[1], dims[2])
        doc: The section parsed by kind; bytes for an extension kind.

  records:
    doc: |
      The `tables` and `materials` sections: arrays of fixed-size records (format-spec.md
      section 9), `dims` [count, record size]. Table i is record i of `tables`, material j
      record j of `materials`. Records are 64 (tables) or 512 (materials) bytes; a file of a
      newer minor may have longer ones, whose first 64 or 512 bytes are as described and whose
      extra bytes are skipped.
    params:
      - id: kind
        type: u4
        enum: section_kind
      - id: n_records
        type: u4
      - id: record_size
        type: u4
    seq:
      - id: records
        size: record_size
        type:
          switch-on: kind
          cases:
            section_kind::tables: table_record
            section_kind::materials: material_record
        repeat: expr
        repeat-expr: n_records

  table_record:
    doc: |
      One table (format-spec.md section 9.1), in reduced units: independent of g, except a
      walk-angular table (model 3), which holds the g of its walk. Bytes 28 to 63 depend on
      the model: `ridge` then reserved bytes in a pbd-angular record, `component`, `g`,
      `ridge` then reserved bytes in a walk-angular one.
    seq:
      - id: model
        type: u4
        enum: model
        valid:
          in-enum: true
        doc: The model the table tabulates.
      - id: fresnel
        type: u4
        enum: fresnel
        valid:
          in-enum: true
        doc: Convention of the Fresnel moments.
      - id: eta
        type: f8
        valid:
          expr: _ > 0 and _ <= 1.7976931348623157e308
        doc: Relative index of refraction η the table was baked for, finite and > 0.
      - id: n_rho
        type: u4
        valid:
          min: 1
          max: 65536
        doc: nρ, number of reduced-albedo rows.
      - id: n_theta
        type: u4
        valid:
          min: 1
          max: 65536
        doc: nθ, number of incidence angles.
      - id: n_r
        type: u4
        valid:
          min: 1
          max: 65536
        doc: nr, number of radii.
      - id: component
        type: u4
        enum: walk_component
        if: model == model::walk_angular
        valid:
          in-enum: true
        doc: What a walk-angular table holds (bytes 28 to 31; reserved in other models).
      - id: g
        type: f8
        if: model == model::walk_angular
        valid:
          expr: _ > -1 and _ < 1
        doc: |
          Henyey–Greenstein asymmetry g of a walk-angular table's walk, finite and in (−1, 1)
          (bytes 32 to 39; reserved in other models).
      - id: ridge
        type: u4
        valid:
          max: 2
        doc: |
          Since 1.6 (required feature bit 6): 0 the nodes hold the profile S, 1 they hold
          S less the analytic ridge R of format-spec.md section 10, which every lookup adds
          back, 2 they hold the profile less the ridge with its fluence part (section 10),
          which every lookup adds back. Bytes 28 to 31 of a pbd-angular record, 40 to 43 of
          a walk-angular one; reserved zero, hence 0, in files of older minors.
      - id: reserved
        size: 'model == model::walk_angular ? 20 : 32'
        doc: Zero (not checked here); from byte 44 in a walk-angular record, else from byte 32.

  material_record:
    doc: |
      One material (format-spec.md section 9.2): a medium's coefficients per channel (R, G,
      B) and the table each channel is rendered with.
    seq:
      - id: name_len
        type: u4
        valid:
          min: 1
          max: 64
        doc: Bytes of `name` used.
      - id: source_len
        type: u4
        valid:
          max: 256
        doc: Bytes of `source` used.
      - id: table
        type: u4
        repeat: expr
        repeat-expr: 3
        doc: Index of the table each channel (R, G, B) uses, < n_tables (not checked here).
      - id: flags
        type: u4
        doc: Bit 0, the albedo range is meaningful. Bits 1 to 31 reserved.
      - id: sigma_s
        type: f8
        repeat: expr
        repeat-expr: 3
        valid:
          expr: _ >= 0 and _ <= 1.7976931348623157e308
        doc: Scattering coefficient σs per channel, mm⁻¹, finite and ≥ 0.
      - id: sigma_a
        type: f8
        repeat: expr
        repeat-expr: 3
        valid:
          expr: _ >= 0 and _ <= 1.7976931348623157e308
        doc: Absorption coefficient σa per channel, mm⁻¹, finite and ≥ 0.
      - id: g
        type: f8
        repeat: expr
        repeat-expr: 3
        valid:
          expr: _ > -1 and _ < 1
        doc: Henyey–Greenstein asymmetry g per channel, in (−1, 1).
      - id: eta
        type: f8
        valid:
          expr: _ > 0 and _ <= 1.7976931348623157e308
        doc: Relative index of refraction η, finite and > 0.
      - id: albedo_min
        type: f8
        repeat: expr
        repeat-expr: 3
        valid:
          expr: _ >= 0 and _ <= 1
        doc: Lowest reduced albedo ρ′ the scene needs, per channel, in [0, 1] (0 without flag bit 0).
      - id: albedo_max
        type: f8
        repeat: expr
        repeat-expr: 3
        valid:
          expr: _ >= 0 and _ <= 1
        doc: |
          Highest reduced albedo ρ′ the scene needs, per channel, in [albedo_min, 1] (0
          without flag bit 0).
      - id: reserved
        size: 40
        doc: Zero (not checked here).
      - id: name
        type: str
        encoding: UTF-8
        size: name_len
        doc: The material's name, unique within the file, without control characters.
      - id: name_unused
        size: 64 - name_len
        doc: The unused bytes of the 64-byte name field, zero.
      - id: source
        type: str
        encoding: UTF-8
        size: source_len
        doc: Where the coefficients come from, without control characters.
      - id: source_unused
        size: 256 - source_len
        doc: The unused bytes of the 256-byte source field, zero.
    instances:
      has_albedo_range:
        value: (flags & 1) != 0
        doc: Flag bit 0, the albedo range is meaningful.

  provenance:
    doc: |
      How the file was made: one JSON object (RFC 8259) in UTF-8, at most 1 MiB, written
      canonically (format-spec.md section 11). Its keys are not described here.
    seq:
      - id: json
        type: str
        encoding: UTF-8
        size-eos: true

  axis:
    doc: |
      One axis of a table, strictly increasing: `axis-rho`, reduced albedo ρ′ in [0, 1];
      `axis-theta`, incidence angle θ in radians in [0, π/2]; `axis-r`, radius in reduced mean
      free paths, ≥ 0 (format-spec.md section 10).
    params:
      - id: n_values
        type: u4
    seq:
      - id: values
        type: f4
        repeat: expr
        repeat-expr: n_values

  node_grid:
    doc: |
      A section with one record per node (i, j, k) = (ρ′, θ, r) of the table's nρ × nθ × nr
      grid: `gwc-params` or `gwc-harmonics`. Node (i, j, k) is `nodes[(i · nθ + j) · nr + k]`
      (format-spec.md section 10).
    params:
      - id: kind
        type: u4
        enum: section_kind
      - id: n_rho
        type: u4
      - id: n_theta
        type: u4
      - id: n_r
        type: u4
    seq:
      - id: nodes
        type:
          switch-on: kind
          cases:
            section_kind::gwc_params: gwc_node
            section_kind::gwc_harmonics: harmonics_node
        repeat: expr
        repeat-expr: n_rho * n_theta * n_r

  gwc_node:
    doc: |
      A node of `gwc-params`: the General Wrapped Cauchy profile over the exit azimuth,
      f(φ) = α + β·pdf_WC(φ; c), stored as (E, E_β, c); β = E_β/r and α = (E − E_β)/(2πr) at
      r > 0. The node rules of format-spec.md section 10 are not checked here.
    seq:
      - id: e
        type: f4
        doc: Radial energy E = (2πα + β)·r.
      - id: e_beta
        type: f4
        doc: The lobe's share of it, E_β = β·r; above E where the floor α is negative.
      - id: c
        type: f4
        doc: Concentration c of the wrapped Cauchy lobe, in (−1, 1).

  radial_cdf:
    doc: |
      For each (i, j), the running integral over r of the spline through E, 0 at the first
      radius; the last value is the effective albedo ρ_eff(ρ′_i, θ_j). Element (i, j, k) is
      `values[(i · nθ + j) · nr + k]`.
    params:
      - id: n_rho
        type: u4
      - id: n_theta
        type: u4
      - id: n_r
        type: u4
    seq:
      - id: values
        type: f4
        repeat: expr
        repeat-expr: n_rho * n_theta * n_r

  theta_cdf:
    doc: |
      For each i, the running integral over θ of the spline through ρ_eff(ρ′_i, θ_j), 0 at
      the first angle (optional, for sampling θ). Element (i, j) is `values[i · nθ + j]`.
    params:
      - id: n_rho
        type: u4
      - id: n_theta
        type: u4
    seq:
      - id: values
        type: f4
        repeat: expr
        repeat-expr: n_rho * n_theta

  harmonics_node:
    doc: |
      A node of `gwc-harmonics` (since 1.2, required feature bit 2): the table's profile has
      two lobes, stored by its third and fourth harmonics times r, where
      μₙ = ∫ f(φ) cos nφ dφ; `gwc-params` then holds the one lobe with the same first two.
    seq:
      - id: r_mu3
        type: f4
        doc: r·μ₃.
      - id: r_mu4
        type: f4
        doc: r·μ₄.

enums:
  section_kind:
    0x01:
      id: tables
      doc: File level; u8 [n_tables, 64]; required; exactly one.
    0x02:
      id: materials
      doc: File level; u8 [n_materials, 512]; required; exactly one.
    0x03:
      id: provenance
      doc: File level; u8 [len]; not required; at most one.
    0x10:
      id: axis_rho
      doc: Per table; f32 [nρ]; required; one per table.
    0x11:
      id: axis_theta
      doc: Per table; f32 [nθ]; required; one per table.
    0x12:
      id: axis_r
      doc: Per table; f32 [nr]; required; one per table.
    0x20:
      id: gwc_params
      doc: Per table; f32 [nρ, nθ, nr, 3]; required; one per table.
    0x21:
      id: radial_cdf
      doc: Per table; f32 [nρ, nθ, nr]; required; one per table.
    0x22:
      id: theta_cdf
      doc: Per table; f32 [nρ, nθ]; not required; at most one per table.
    0x23:
      id: gwc_harmonics
      doc: Per table; f32 [nρ, nθ, nr, 2]; required; at most one per table (since 1.2).
  dtype:
    1:
      id: u8
      doc: Bytes, 1 each; fixed records or UTF-8 text.
    2:
      id: f32
      doc: IEEE 754 binary32, little-endian, 4 bytes each.
  codec:
    0:
      id: none
      doc: The stored bytes are the data; a reader may map them and use them in place.
    1:
      id: zstd
      doc: |
        One or more zstd frames (RFC 8878) that decode to exactly `raw_len` bytes; requires
        required feature bit 0.
  model:
    1:
      id: pbd_angular
      doc: |
        Photon beam diffusion at any incidence, tabulated as Ferrier's General Wrapped Cauchy
        fit over φ. (2 is reserved for pbd-perpendicular.)
    3:
      id: walk_angular
      doc: |
        The Monte Carlo random walk at any incidence for one g (since 1.5, required feature
        bit 5), tabulated as a two-lobe pbd-angular table: the same sections, with
        gwc-harmonics required.
  walk_component:
    0:
      id: multiple
      doc: Multiple scattering (exits after two or more scattering events).
    1:
      id: total
      doc: Everything that leaves, single scattering included.
  fresnel:
    0:
      id: exact
      doc: Exact Fresnel moments.
    1:
      id: pbrt
      doc: pbrt's polynomial Fresnel moments.
