// Runs the golden shots compiled to WebAssembly and prints their results, one line each as
// shared/tests/golden/hashes.txt lists them: `node run.mjs path/to/breakshot_web_golden.wasm`.
// The module imports nothing; a module that did would fail to instantiate here, which is
// wanted: the browser build must not need host functions for its physics.
import { readFile } from "node:fs/promises";

const path = process.argv[2];
if (!path) {
  console.error("usage: node run.mjs MODULE.wasm");
  process.exit(2);
}
const { instance } = await WebAssembly.instantiate(await readFile(path), {});
const { golden_run, golden_ptr, memory } = instance.exports;
const len = golden_run();
const ptr = golden_ptr();
if (ptr === 0) {
  console.error("golden_ptr is null after golden_run");
  process.exit(1);
}
// Read the memory only now: running may have grown it, which replaces its buffer.
const bytes = new Uint8Array(memory.buffer, ptr, len);
process.stdout.write(new TextDecoder("utf-8", { fatal: true }).decode(bytes));
