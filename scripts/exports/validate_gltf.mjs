// The Khronos glTF validator (npm `gltf-validator`) over glTF files: each file's report in one
// line (its errors, warnings, infos and hints), every message of severity error or warning
// printed, and exit 1 when any file has an error.
//
//   node scripts/exports/validate_gltf.mjs NODE_PREFIX FILE.gltf...
//
// NODE_PREFIX is the folder `npm install --prefix NODE_PREFIX gltf-validator` installed into
// (scripts/exports/ci.sh's target/exports-node).
// External resources (the .bin and the textures) are read beside each file, so a texture that is
// missing or not a PNG of its declared size is reported, as the validator reports it.
import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import path from "node:path";

const [prefix, ...files] = process.argv.slice(2);
if (!prefix || files.length === 0) {
  console.error("usage: node validate_gltf.mjs NODE_PREFIX FILE.gltf...");
  process.exit(2);
}
const require = createRequire(path.resolve(prefix, "package.json"));
const validator = require("gltf-validator");
console.log(`gltf-validator ${validator.version()}`);

let failed = 0;
for (const file of files) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) =>
      readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then(
        (b) => new Uint8Array(b),
      ),
  });
  const i = report.issues;
  const info = report.info || {};
  console.log(
    `${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
      `${i.numHints} hints; extensions used: ${(info.extensionsUsed || []).join(", ")}; ` +
      `resources: ${(info.resources || []).length}`,
  );
  for (const m of i.messages) {
    // Severity: 0 error, 1 warning, 2 info, 3 hint.
    if (m.severity <= 1) {
      console.log(`  ${["error", "warning"][m.severity]} ${m.code} at ${m.pointer || "-"}: ${m.message}`);
    }
  }
  if (i.numErrors > 0) failed += 1;
}
if (failed > 0) {
  console.error(`${failed} of ${files.length} glTF files have errors`);
  process.exit(1);
}
console.log(`all ${files.length} glTF files pass (no errors)`);
