// LZMA decoder for dynref view's data files (ref/view/packed.h LzmaLatin1: the ".lzma" format of
// liblzma's lzma_alone_encoder, 13-byte header + range-coded LZMA1 stream ending with the end
// marker). Written for this page from the LZMA format description (the browser's
// DecompressionStream has only gzip/deflate). lzmaDecode(bytes) -> Uint8Array.
//
// Speed: the range decoder's state (range, code: unsigned 32-bit values held as int32 bit
// patterns, compared unsigned by flipping the sign bit, x ^ MIN) must stay in local variables of
// one function, or V8 keeps it in memory (closure slots, typed arrays) and decodes 2-3x slower. So
// the decoder is one function whose repeated steps (decode a bit, a bit tree, a length) are
// written once below as source templates and expanded into it when the page loads.
'use strict';

const lzmaDecode = (() => {
  // Decodes one bit with probability P[i] into variable `b`.
  const BIT = (i, b) => `{ const p_ = P[${i}], bound_ = Math.imul(range >>> 11, p_);
    if ((code ^ MIN) < (bound_ ^ MIN)) { range = bound_; P[${i}] = p_ + ((2048 - p_) >>> 5); ${b} = 0; }
    else { range = (range - bound_) | 0; code = (code - bound_) | 0; P[${i}] = p_ - (p_ >>> 5); ${b} = 1; }
    if ((range >>> 24) === 0) { range <<= 8; code = (code << 8) | input[inPos++]; } }`;
  // A bit tree of n bits at probabilities base + 1 .., most significant bit first, into `out`.
  const TREE = (base, n, out) => `{ let m_ = 1, t_ = 0;
    for (let i_ = 0; i_ < ${n}; ++i_) { ${BIT(`${base} + m_`, 't_')} m_ = (m_ << 1) + t_; }
    ${out} = m_ - (1 << ${n}); }`;
  // The same, least significant bit first.
  const REVERSE = (base, n, out) => `{ let m_ = 1, s_ = 0, t_ = 0;
    for (let i_ = 0; i_ < ${n}; ++i_) { ${BIT(`${base} + m_`, 't_')} m_ = (m_ << 1) + t_; s_ |= t_ << i_; }
    ${out} = s_; }`;
  // A match length - 2 with the length coder at L: choice, choice2, low[16][8], mid[16][8], high[256].
  const LENGTH = (L, out) => `{ let c_ = 0; ${BIT(L, 'c_')}
    if (c_ === 0) ${TREE(`${L} + 2 + ps * 8`, 3, out)}
    else { ${BIT(`${L} + 1`, 'c_')}
      if (c_ === 0) { ${TREE(`${L} + 130 + ps * 8`, 3, out)} ${out} += 8; }
      else { ${TREE(`${L} + 258`, 8, out)} ${out} += 16; } } }`;
  const body = `
  const d = input[0];
  if (d >= 225) throw new Error('bad LZMA properties');
  const lc = d % 9, lp = Math.floor(d / 9) % 5, pb = Math.floor(d / 45);
  let known = -1;  // uncompressed size from the header, -1 when unknown (0xFF x 8)
  let allFF = true;
  for (let i = 5; i < 13; ++i) allFF = allFF && input[i] === 0xff;
  if (!allFF) { known = 0; for (let i = 12; i >= 5; --i) known = known * 256 + input[i]; }
  let out = new Uint8Array(Math.max(1024, known > 0 ? known : input.length * 6)), pos = 0, inPos = 13;
  const MIN = -2147483648;
  let range = -1, code = 0;
  if (input[inPos++] !== 0) throw new Error('bad LZMA stream');
  for (let i = 0; i < 4; ++i) code = (code << 8) | input[inPos++];
  // Every probability in one array P, at these offsets.
  const LIT = 0, IS_MATCH = LIT + (0x300 << (lc + lp)), IS_REP = IS_MATCH + 192, IS_REP_G0 = IS_REP + 12;
  const IS_REP_G1 = IS_REP_G0 + 12, IS_REP_G2 = IS_REP_G1 + 12, IS_REP0_LONG = IS_REP_G2 + 12;
  const SLOT = IS_REP0_LONG + 192, SPECIAL = SLOT + 256, ALIGN = SPECIAL + 115, MATCH_LEN = ALIGN + 16;
  const REP_LEN = MATCH_LEN + 514, P = new Uint16Array(REP_LEN + 514).fill(1024);
  const pbMask = (1 << pb) - 1, lpMask = (1 << lp) - 1;
  let state = 0, rep0 = 0, rep1 = 0, rep2 = 0, rep3 = 0, bit = 0, len = 0;
  while (known < 0 || pos < known) {
    if (pos + 300 > out.length) { const bigger = new Uint8Array(out.length * 2); bigger.set(out); out = bigger; }
    const ps = pos & pbMask;
    ${BIT('IS_MATCH + (state << 4) + ps', 'bit')}
    if (bit === 0) {  // a literal; after a match the byte at rep0 guides its first bits
      const base = LIT + 0x300 * (((pos & lpMask) << lc) + ((pos > 0 ? out[pos - 1] : 0) >>> (8 - lc)));
      let sym = 1;
      if (state >= 7) {
        let m = out[pos - rep0 - 1];
        while (sym < 0x100) {
          const mb = (m >>> 7) & 1;
          m <<= 1;
          ${BIT('base + ((1 + mb) << 8) + sym', 'bit')}
          sym = (sym << 1) | bit;
          if (mb !== bit) break;
        }
      }
      while (sym < 0x100) { ${BIT('base + sym', 'bit')} sym = (sym << 1) | bit; }
      out[pos++] = sym - 0x100;
      state = state < 4 ? 0 : state < 10 ? state - 3 : state - 6;
      continue;
    }
    ${BIT('IS_REP + state', 'bit')}
    if (bit === 0) {  // a match at a new distance
      rep3 = rep2; rep2 = rep1; rep1 = rep0;
      ${LENGTH('MATCH_LEN', 'len')}
      state = state < 7 ? 7 : 10;
      let s = 0;
      ${TREE('SLOT + Math.min(len, 3) * 64', 6, 's')}
      if (s < 4) rep0 = s;
      else {
        const n = (s >>> 1) - 1;
        let dist = (2 | (s & 1)) * Math.pow(2, n), low = 0;
        if (s < 14) { ${REVERSE('SPECIAL + dist - s', 'n', 'low')} dist += low; }
        else {
          let direct = 0;
          for (let i = 0; i < n - 4; ++i) {
            range >>>= 1;
            let t = 0;
            if ((code ^ MIN) >= (range ^ MIN)) { code = (code - range) | 0; t = 1; }
            direct = direct * 2 + t;
            if ((range >>> 24) === 0) { range <<= 8; code = (code << 8) | input[inPos++]; }
          }
          ${REVERSE('ALIGN', 4, 'low')}
          dist += direct * 16 + low;
        }
        rep0 = dist;
      }
      if (rep0 === 0xffffffff) break;  // end marker
    } else {
      ${BIT('IS_REP_G0 + state', 'bit')}
      if (bit === 0) {
        ${BIT('IS_REP0_LONG + (state << 4) + ps', 'bit')}
        if (bit === 0) {  // one byte at rep0
          if (rep0 >= pos) throw new Error('bad LZMA distance');
          state = state < 7 ? 9 : 11;
          out[pos] = out[pos - rep0 - 1];
          ++pos;
          continue;
        }
      } else {
        let dist = 0;
        ${BIT('IS_REP_G1 + state', 'bit')}
        if (bit === 0) dist = rep1;
        else {
          ${BIT('IS_REP_G2 + state', 'bit')}
          if (bit === 0) dist = rep2;
          else { dist = rep3; rep3 = rep2; }
          rep2 = rep1;
        }
        rep1 = rep0; rep0 = dist;
      }
      ${LENGTH('REP_LEN', 'len')}
      state = state < 7 ? 8 : 11;
    }
    if (rep0 >= pos) throw new Error('bad LZMA distance');
    for (let n = len + 2, from = pos - rep0 - 1; n > 0; --n) out[pos++] = out[from++];
  }
  return out.subarray(0, pos);`;
  return new Function('input', body);
})();
if (typeof module !== 'undefined') module.exports = { lzmaDecode };
