#!/usr/bin/env node
// Regenerates the Python parser format/python/bssrdf.py from format/bssrdf.ksy with the
// Kaitai Struct compiler (its JavaScript build), and records in format/python/GENERATED_FROM
// which .ksy (SHA-256) and which compiler made it; format/tests/test_ksy.py checks the record.
//
//   node format/generate.js NODE_MODULES
//
// NODE_MODULES is a folder where `kaitai-struct-compiler` (0.11.0) and `js-yaml` (5.5.0) are
// installed, outside the repository (see format/README.md). This script installs nothing.
"use strict";

const crypto = require("crypto");
const fs = require("fs");
const path = require("path");

const modules = process.argv[2];
if (!modules) {
  console.error("usage: node format/generate.js NODE_MODULES");
  process.exit(1);
}
const compiler = require(path.resolve(modules, "kaitai-struct-compiler"));
const yaml = require(path.resolve(modules, "js-yaml"));

const here = __dirname;
const ksyPath = path.join(here, "bssrdf.ksy");
const outDir = path.join(here, "python");
const source = fs.readFileSync(ksyPath, "utf8");

compiler
  .compile("python", yaml.load(source), null, false)
  .then((files) => {
    fs.mkdirSync(outDir, { recursive: true });
    for (const [name, text] of Object.entries(files)) {
      fs.writeFileSync(path.join(outDir, name), text);
      console.log(`wrote format/python/${name}`);
    }
    const sha = crypto.createHash("sha256").update(source).digest("hex");
    fs.writeFileSync(
      path.join(outDir, "GENERATED_FROM"),
      `${sha}  format/bssrdf.ksy\nkaitai-struct-compiler ${compiler.version}\n`,
    );
  })
  .catch((err) => {
    console.error(`format/bssrdf.ksy: ${err}`);
    process.exit(1);
  });
