/*
 * bssrdf_read: an independent reader of bssrdf-zoo library files, written from
 * format-spec.md alone (no code shared with the Rust crate). It maps a file, checks
 * the magic, the version, the file size, the header CRC, then finds one section,
 * checks its CRC and prints one f32 value of it.
 *
 *   cc -std=c99 -O2 -o bssrdf_read bssrdf_read.c
 *   ./bssrdf_read FILE TABLE KIND INDEX
 *
 * TABLE is a table index (or -1 for a file-level section), KIND a section kind code
 * (e.g. 0x20 for gwc-params), INDEX an element index. Prints the value as
 * "<bits in hex> <value>". Exit status: 0 success, 1 usage, 2 I/O error, 3 invalid or
 * unsupported file. Uncompressed files only: a packed file (required feature bit 0,
 * zstd) is rejected as unsupported, as the spec allows. Required feature bit 1
 * (signed-floor, format 1.1: gwc-params nodes with E_beta > E) is implemented: it changes
 * how the values are interpreted, not how they are stored, and this reader prints the
 * stored values. So is required feature bit 2 (harmonics, format 1.2: a gwc-harmonics
 * section, kind 0x23, makes a table's profile two lobes); a file with such a section that
 * does not set the bit is rejected. So are required feature bits 3 (signed-lobes, format 1.3:
 * nodes of gwc-harmonics that are a sharp lobe less a broader one), 4 (merged-roots,
 * format 1.4: how lookups rebuild two lobes from the harmonics), 5 (walk-tables, format
 * 1.5: a table record of model 3, walk-angular, whose arrays are stored as a two-lobe
 * table's) and 6 (ridge, format 1.6: a table record's `ridge` = 1, whose nodes hold the
 * profile less the analytic ridge of section 10, or 2, less the ridge with its fluence part,
 * which lookups add back; the arrays are stored as any table's). A file with a walk-angular
 * record that does not set bit 5, or a record with `ridge` = 1 or 2 that does not set bit 6,
 * is rejected, and so is a `ridge` other than 0, 1 or 2 (at byte 28 of a pbd-angular record,
 * byte 40 of a walk-angular one). It does
 * not check the values themselves (finite, node rules and signed nodes of section 10). Files
 * of any minor of major 1 are read, as section 4 requires of a reader that implements every
 * required bit the file sets.
 *
 * POSIX (mmap). Handles big-endian hosts by assembling every field byte by byte.
 */
#define _POSIX_C_SOURCE 200809L

#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

/* Sizes and codes of format-spec.md, sections 3, 5, 7. */
#define HEADER_SIZE 128u
#define ENTRY_SIZE 64u
#define MAX_SECTIONS 65536u
#define KNOWN_MAJOR 1u
#define DTYPE_F32 2u
#define CODEC_NONE 0u
#define NO_TABLE 0xFFFFFFFFu
/* Required feature bits this reader implements (section 4): bit 1, signed-floor, bit 2,
 * harmonics, bit 3, signed-lobes, bit 4, merged-roots, bit 5, walk-tables, and bit 6, ridge
 * (it prints stored values, whose storage no bit changes). */
#define KNOWN_REQUIRED 0x7Eu
#define REQUIRED_HARMONICS 0x4u
#define REQUIRED_WALK_TABLES 0x20u
#define REQUIRED_RIDGE 0x40u
#define KIND_TABLES 0x1u
#define KIND_HARMONICS 0x23u
#define TABLE_RECORD_SIZE 64u
#define MODEL_PBD_ANGULAR 1u
#define MODEL_WALK_ANGULAR 3u
/* Offset of `ridge` (u32) within a table record, by model (section 9.1) */
#define RIDGE_OFFSET_PBD 28u
#define RIDGE_OFFSET_WALK 40u
/* The largest known `ridge`: 0 none, 1 the flux ridge, 2 the ridge with its fluence part */
#define RIDGE_MAX 2u

static const unsigned char MAGIC[12] = {0x89, 'B', 'S', 'S', 'R', 'D',
                                        'F',  '\r', '\n', 0x1A, '\n', 0x00};

/* Little-endian loads (section 2: everything is little-endian). */
static uint16_t le16(const unsigned char *p) { return (uint16_t)(p[0] | (p[1] << 8)); }

static uint32_t le32(const unsigned char *p) {
  return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
         ((uint32_t)p[3] << 24);
}

static uint64_t le64(const unsigned char *p) {
  return (uint64_t)le32(p) | ((uint64_t)le32(p + 4) << 32);
}

/* CRC-32, reflected polynomial 0xEDB88320, init and final XOR 0xFFFFFFFF (section 2). */
static uint32_t crc_table[256];

static void crc_init(void) {
  for (uint32_t n = 0; n < 256; n++) {
    uint32_t c = n;
    for (int k = 0; k < 8; k++) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    crc_table[n] = c;
  }
}

/* CRC of a byte run, continuing `crc`: crc_update(crc_update(0, a), b) is the CRC of a
 * followed by b. */
static uint32_t crc_update(uint32_t crc, const unsigned char *p, uint64_t n) {
  crc = ~crc;
  for (uint64_t i = 0; i < n; i++) crc = crc_table[(crc ^ p[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

static int fail(const char *message) {
  fprintf(stderr, "bssrdf_read: %s\n", message);
  return 3;
}

int main(int argc, char **argv) {
  if (argc != 5) {
    fprintf(stderr, "usage: %s FILE TABLE KIND INDEX\n", argv[0]);
    return 1;
  }
  long long table_arg = strtoll(argv[2], NULL, 0);
  uint32_t want_table = table_arg < 0 ? NO_TABLE : (uint32_t)table_arg;
  uint32_t want_kind = (uint32_t)strtoul(argv[3], NULL, 0);
  uint64_t want_index = (uint64_t)strtoull(argv[4], NULL, 0);
  crc_init();

  int fd = open(argv[1], O_RDONLY);
  if (fd < 0) {
    perror("bssrdf_read: open");
    return 2;
  }
  struct stat st;
  if (fstat(fd, &st) != 0) {
    perror("bssrdf_read: fstat");
    return 2;
  }
  uint64_t size = (uint64_t)st.st_size;
  if (size < HEADER_SIZE) return fail("file shorter than the 128-byte header");
  const unsigned char *f = mmap(NULL, (size_t)size, PROT_READ, MAP_PRIVATE, fd, 0);
  close(fd);
  if (f == MAP_FAILED) {
    perror("bssrdf_read: mmap");
    return 2;
  }

  /* Header (section 3), checked in the order of section 14. */
  if (memcmp(f, MAGIC, sizeof MAGIC) != 0) return fail("bad magic: not a library file");
  if (le32(f + 16) != 0x0A0B0C0Du) return fail("bad byte-order mark");
  uint16_t major = le16(f + 12), minor = le16(f + 14);
  if (major != KNOWN_MAJOR) return fail("unsupported major version");
  if (le64(f + 24) != size) return fail("declared file size differs from the real size");
  uint64_t count = le32(f + 20);
  uint64_t dir_end = HEADER_SIZE + count * ENTRY_SIZE;
  if (count > MAX_SECTIONS || dir_end > size) return fail("directory out of bounds");
  uint32_t crc = crc_update(crc_update(0, f, 124), f + HEADER_SIZE, dir_end - HEADER_SIZE);
  if (crc != le32(f + 124)) return fail("header crc mismatch");
  if ((le64(f + 32) & ~(uint64_t)KNOWN_REQUIRED) != 0)
    return fail("file needs required features (e.g. zstd, bit 0) this reader lacks");
  uint32_t alignment = le32(f + 48);
  if (alignment < 256u || alignment > 65536u || (alignment & (alignment - 1u)) != 0)
    return fail("bad alignment");

  /* Features a section needs must be declared (section 4), whichever section is asked for:
   * a gwc-harmonics section (kind 0x23, two lobes) needs bit 2, and a compressed section
   * needs bit 0, which this reader lacks (a file declaring it was refused above). */
  uint64_t required = le64(f + 32);
  for (uint64_t i = 0; i < count; i++) {
    const unsigned char *e = f + HEADER_SIZE + i * ENTRY_SIZE;
    if (le32(e) == KIND_HARMONICS && (required & REQUIRED_HARMONICS) == 0)
      return fail("gwc-harmonics section without required feature bit 2 (harmonics)");
    if (le16(e + 10) != CODEC_NONE)
      return fail("compressed section without required feature bit 0 (zstd)");
    /* The tables section (kind 1, u8 records of dims[1] bytes, section 9): a walk-angular
     * record (model 3 at byte 0) needs bit 5, and a record whose `ridge` is 1 or 2 needs
     * bit 6 */
    if (le32(e) == KIND_TABLES && le32(e + 4) == NO_TABLE && le16(e + 14) == 2) {
      uint64_t records = le32(e + 16), record_size = le32(e + 20);
      uint64_t offset = le64(e + 32), stored = le64(e + 40);
      if (record_size < TABLE_RECORD_SIZE || offset > size || stored > size - offset ||
          records > stored / record_size)
        return fail("tables section out of bounds or with records shorter than 64 bytes");
      for (uint64_t t = 0; t < records; t++) {
        const unsigned char *record = f + offset + t * record_size;
        uint32_t model = le32(record);
        if (model == MODEL_WALK_ANGULAR && (required & REQUIRED_WALK_TABLES) == 0)
          return fail("walk-angular table without required feature bit 5 (walk-tables)");
        if (model != MODEL_PBD_ANGULAR && model != MODEL_WALK_ANGULAR) continue;
        uint32_t ridge =
            le32(record + (model == MODEL_WALK_ANGULAR ? RIDGE_OFFSET_WALK : RIDGE_OFFSET_PBD));
        if (ridge > RIDGE_MAX) return fail("table record with an unknown ridge code (0, 1 or 2)");
        if (ridge != 0u && (required & REQUIRED_RIDGE) == 0)
          return fail("table with ridge = 1 or 2 without required feature bit 6 (ridge)");
      }
    }
  }

  /* Directory (section 5): find the entry. */
  for (uint64_t i = 0; i < count; i++) {
    const unsigned char *e = f + HEADER_SIZE + i * ENTRY_SIZE;
    if (le32(e) != want_kind || le32(e + 4) != want_table) continue;
    uint16_t dtype = le16(e + 8), codec = le16(e + 10), ndim = le16(e + 14);
    uint64_t offset = le64(e + 32), stored = le64(e + 40), raw = le64(e + 48);
    if (dtype != DTYPE_F32) return fail("section is not f32");
    if (codec != CODEC_NONE) return fail("section is compressed");
    if (ndim < 1 || ndim > 4) return fail("bad ndim");
    uint64_t elements = 1; /* product of dims, kept below the file size: no overflow */
    for (uint16_t d = 0; d < ndim; d++) {
      uint64_t dim = le32(e + 16 + 4u * d);
      if (dim != 0 && elements > size / dim) return fail("section larger than the file");
      elements *= dim;
    }
    if (raw != elements * 4u || stored != raw) return fail("section length mismatch");
    if (offset % alignment != 0) return fail("misaligned section");
    if (offset > size || stored > size - offset) return fail("section out of bounds");
    if (crc_update(0, f + offset, stored) != le32(e + 56)) return fail("section crc mismatch");
    if (want_index >= elements) return fail("index out of range");

    uint32_t bits = le32(f + offset + 4u * want_index);
    float value;
    memcpy(&value, &bits, sizeof value); /* IEEE 754 binary32 on every host we target */
    printf("%08x %.9g\n", (unsigned)bits, (double)value);
    fprintf(stderr, "format %u.%u, %llu sections\n", (unsigned)major, (unsigned)minor,
            (unsigned long long)count);
    munmap((void *)f, (size_t)size);
    return 0;
  }
  return fail("no such section");
}
