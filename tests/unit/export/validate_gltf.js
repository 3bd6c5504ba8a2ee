// Runs the Khronos glTF validator (npm package gltf-validator) on one .glb and prints its messages.
// Usage: node validate_gltf.js VALIDATOR_MODULE_DIR FILE.glb
// Exit status: 0 valid (no errors), 1 errors found, 2 the validator could not run.
const fs = require('fs');
const [moduleDir, file] = process.argv.slice(2);
let validator;
try {
  validator = require(moduleDir);
} catch (e) {
  console.error('cannot load gltf-validator from ' + moduleDir + ': ' + e.message);
  process.exit(2);
}
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {maxIssues: 100})
    .then((report) => {
      const issues = report.issues;
      console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                  `${issues.numInfos} infos, ${issues.numHints} hints`);
      for (const m of issues.messages) console.log(`  [${m.severity}] ${m.code} ${m.pointer || ''}: ${m.message}`);
      process.exit(issues.numErrors > 0 ? 1 : 0);
    })
    .catch((e) => {
      console.error('validation failed: ' + e);
      process.exit(2);
    });
