// Validates glTF files with the Khronos glTF Validator (the npm package
// gltf-validator): node web/validate_gltf.mjs FILE.gltf|FILE.glb ...
// Prints each file's counts of errors, warnings, infos and hints and every
// error and warning; exits 1 when a file has an error or a warning, 2 when
// it cannot be read.
import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

let status = 0;
for (const file of process.argv.slice(2)) {
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (e) {
    console.error(`error: ${file}: ${e.message}`);
    process.exit(2);
  }
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)),
                    (err, data) => (err ? reject(err.toString()) : resolve(data)));
      }),
  });
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ` +
              `${i.numInfos} infos, ${i.numHints} hints ` +
              `(validator ${report.validatorVersion})`);
  for (const m of i.messages) {
    if (m.severity <= 1) {
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ` +
                  `at ${m.pointer ?? ''}: ${m.message}`);
    }
  }
  if (i.numErrors > 0 || i.numWarnings > 0) status = 1;
}
process.exit(status);
