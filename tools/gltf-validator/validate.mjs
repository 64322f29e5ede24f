// Runs the Khronos glTF validator on one .glb or .gltf and prints its report
// as JSON. Exit 0 when the file has no errors and no warnings, 1 when it has
// some, 2 when it cannot be read. Used by the tests on the pipeline's
// preview.glb (README, "Outputs").
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

const path = process.argv[2];
if (!path) {
  console.error('usage: node validate.mjs FILE.glb');
  process.exit(2);
}
let bytes;
try {
  bytes = new Uint8Array(await readFile(path));
} catch (e) {
  console.error(`${path}: ${e.message}`);
  process.exit(2);
}
const report = await validator.validateBytes(bytes, { uri: path, maxIssues: 100 });
console.log(JSON.stringify({
  errors: report.issues.numErrors,
  warnings: report.issues.numWarnings,
  infos: report.issues.numInfos,
  hints: report.issues.numHints,
  extensionsUsed: report.info ? report.info.extensionsUsed || [] : [],
  messages: report.issues.messages,
}, null, 2));
process.exit(report.issues.numErrors === 0 && report.issues.numWarnings === 0 ? 0 : 1);
