// node zstd_files.cjs FILE...: replaces each file by its zstd frame (@foxglove/wasm-zstd), as
// rosbag2 compresses messages with compression_mode MESSAGE.
"use strict";
const fs = require("fs");
const zstd = require("@foxglove/wasm-zstd");

zstd.isLoaded.then(() => {
  for (const file of process.argv.slice(2)) fs.writeFileSync(file, zstd.compress(fs.readFileSync(file), 3));
}).catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
