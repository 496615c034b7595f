// Validates a .glb with the Khronos glTF-Validator (npm gltf-validator) and prints its report
// as JSON on stdout. Usage: node validate_gltf.mjs NODE_MODULES FILE.glb
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";

const [modules, file] = process.argv.slice(2);
const require = createRequire(path.join(modules, "noop.js"));
const validator = require("gltf-validator");
const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
  maxIssues: 0,
  writeTimestamp: false,
});
console.log(JSON.stringify(report));
