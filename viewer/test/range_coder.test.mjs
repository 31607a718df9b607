// The browser's range decoder (src/dpm/range_coder.js) on the bytes the C++ encoder writes for a
// fixed sequence (tests/progressive_range_coder_test.cpp holds the same bytes): the two coders
// agree bit for bit, and a stream cut short or not starting with 0 is refused.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { RangeDecoder, SignedModel, UnsignedModel, bitModels } from '../src/dpm/range_coder.js';
import { encodeSigned, encodeUnsigned, RangeEncoder } from './range_encoder.mjs';

const HEX = '00a9ddf414c9088107e3303e9292b235f6b420802ce7114a78e3de6022a8468d220ac415d1f53e757c22b408d1d1169a73dc9f2042cfdc004d976a004eaee3d1c33afa58178feafb18c8bfc8329d837b12b6e2c1d8c723d33c4be70a0f9ef90da0ba8d547f50e9563c9d1c17ced92ba3b0d32d72001cacaa73811a5c8eefae6dd5720fa8f9ba12174a846bb450dbe402902966678da9544ba8711159bd24027c5ec111ad79853315c09e26f9cbd4af21416fcd34085dcefd1c4db14edcb7ab9297fd30b308981b74db6e1ee1032d1e3e84ff62a5664feb8e47e8593384b9108e41ff5a3c2a5ee0dad91243c9d8b307b63acd5007950e3305cd82f90ab1fd05b660929ffef35934ffffffffffffff9427e67800f9b75d7800';

function bytesOf(hex) {
  const out = new Uint8Array(hex.length / 2);
  for (let i = 0; i < out.length; i++) out[i] = parseInt(hex.slice(2 * i, 2 * i + 2), 16);
  return out;
}

// The fixed sequence: kind i % 3 is a signed value, an unsigned value or a bit.
function expected() {
  const values = [];
  let x = 12345;
  for (let i = 0; i < 200; i++) {
    x = (Math.imul(x, 1103515245) + 12345) >>> 0;
    const mag = (x >>> 8) % (i < 100 ? 9 : 100000);
    if (i % 3 === 0) values.push(x & 1 && mag ? -mag : mag);
    if (i % 3 === 1) values.push(mag);
    if (i % 3 === 2) values.push((x >>> 20) & 1);
  }
  return values;
}

function decodeAll(bytes) {
  const d = new RangeDecoder(bytes);
  const s = new SignedModel();
  const u = new UnsignedModel();
  const b = bitModels(1);
  const got = [];
  for (let i = 0; i < 200; i++) {
    if (i % 3 === 0) got.push(s.decode(d));
    if (i % 3 === 1) got.push(u.decode(d));
    if (i % 3 === 2) got.push(d.bit(b, 0));
  }
  got.push(u.decode(d), s.decode(d), d.direct(10));
  return { d, got };
}

test('the C++ encoder\'s bytes decode to the fixed sequence, using every byte', () => {
  const { d, got } = decodeAll(bytesOf(HEX));
  assert.deepEqual(got.slice(0, 200), expected());
  assert.equal(got[200], 2 ** 53 - 2);
  assert.equal(got[201], -(2 ** 40 + 7));
  assert.equal(got[202], 0x2a5);
  assert.ok(d.ok());
  assert.ok(d.exhausted());
});

test('a stream cut short, or not starting with 0, is not ok', () => {
  const bytes = bytesOf(HEX);
  assert.equal(decodeAll(bytes.subarray(0, bytes.length - 3)).d.ok(), false);
  const damaged = bytes.slice();
  damaged[0] = 1;
  assert.equal(new RangeDecoder(damaged).ok(), false);
});

// The decoder reads an integer's bits in int32 arithmetic while its length allows (n < 2^31)
// and in Numbers beyond: values around every switch-over, coded by the tests' own encoder
// (test/range_encoder.mjs, Numbers throughout), come back exactly, with their signs.
test('integers around 2^30, 2^31, 2^32 and up to 2^53 − 2 decode exactly', () => {
  const values = [];
  for (const e of [0, 1, 2, 3, 24, 25, 26, 28, 29, 30, 31, 32, 33, 40, 52, 53])
    for (const d of [-2, -1, 0, 1]) if (2 ** e + d >= 0 && 2 ** e + d <= 2 ** 53 - 2) values.push(2 ** e + d);
  const e = new RangeEncoder();
  const [su, ss] = [new UnsignedModel(), new SignedModel()];
  for (const v of values) {
    encodeUnsigned(e, su, v);
    encodeSigned(e, ss, v % 2 ? -v : v);
  }
  const bytes = e.finish();
  const d = new RangeDecoder(bytes);
  const [du, ds] = [new UnsignedModel(), new SignedModel()];
  const got = values.map((v) => [du.decode(d), ds.decode(d), v]);
  for (const [u, s, v] of got) {
    assert.equal(u, v);
    assert.equal(s, v % 2 ? -v : v);
  }
  assert.ok(d.ok() && d.exhausted());
  // Cut short anywhere: not ok, and no exception on the way.
  for (const cut of [1, 5, 9, bytes.length >> 1, bytes.length - 1]) {
    const c = new RangeDecoder(bytes.subarray(0, cut));
    const [cu, cs] = [new UnsignedModel(), new SignedModel()];
    for (let i = 0; i < values.length; i++) cu.decode(c), cs.decode(c);
    assert.equal(c.ok(), false);
  }
});
