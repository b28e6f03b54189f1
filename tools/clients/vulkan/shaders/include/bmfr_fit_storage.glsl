// BMFR's block matrix in global memory (docs/bmfr.md, "Storage"), as the authors keep it: one
// 1024 x 13 matrix per block, column-major so that the 256 invocations of a workgroup read
// consecutive words. With binary16 storage two columns share a uint (packHalf2x16: column 2k in
// the low half, 2k + 1 in the high half; 7 words per row); with binary32 storage each column is
// one word (floatBitsToUint; 13 words per row). Every invocation owns its rows: it alone reads
// and writes them, so the matrix needs no barrier.
//
// Needs, before the #include: `m[]` (the uint buffer), p.half_storage (push constant) and
// `matrix_base` (the block's first word).

const int bmfr_pixels = 1024;  // rows of a block's matrix
const int bmfr_columns = 13;   // 10 features and 3 colour channels

// What storing v and loading it back gives: binary16 rounds to nearest even and (as the oracle,
// SPEC §0) saturates at +-65504 instead of overflowing; binary32 keeps v.
float storage_round(float v) {
    if (p.half_storage == 0) return v;
    return unpackHalf2x16(packHalf2x16(vec2(clamp(v, -65504.0, 65504.0), 0.0))).x;
}

// Columns first .. 12 of row `row` into a[first .. 12] (binary16: from the pair that holds
// column `first`; a[13] = 0; the columns before are left as they were).
void load_row(int row, int first, inout float a[14]) {
    if (p.half_storage != 0) {
        for (int pair = first / 2; pair < 7; ++pair) {
            const vec2 v = unpackHalf2x16(m[matrix_base + uint(pair * bmfr_pixels + row)]);
            a[2 * pair] = v.x;
            a[2 * pair + 1] = v.y;
        }
    } else {
        for (int j = first; j < bmfr_columns; ++j)
            a[j] = uintBitsToFloat(m[matrix_base + uint(j * bmfr_pixels + row)]);
        a[13] = 0.0;
    }
}

// Entry (row, column) of the block's matrix.
float load_entry(int row, int column) {
    if (p.half_storage == 0)
        return uintBitsToFloat(m[matrix_base + uint(column * bmfr_pixels + row)]);
    const vec2 v = unpackHalf2x16(m[matrix_base + uint((column / 2) * bmfr_pixels + row)]);
    return (column & 1) == 0 ? v.x : v.y;
}

// Stores a[first .. 12] as row `row`, rounded to the storage precision (binary16: from the pair
// that holds column `first`, so a[first - 1] is stored too when first is odd: the caller passes the
// row as it loaded it).
void store_row(int row, int first, float a[14]) {
    if (p.half_storage != 0) {
        for (int pair = first / 2; pair < 7; ++pair) {
            const vec2 v = clamp(vec2(a[2 * pair], a[2 * pair + 1]), -65504.0, 65504.0);
            m[matrix_base + uint(pair * bmfr_pixels + row)] = packHalf2x16(v);
        }
    } else {
        for (int j = first; j < bmfr_columns; ++j)
            m[matrix_base + uint(j * bmfr_pixels + row)] = floatBitsToUint(a[j]);
    }
}
