// The Khronos glTF validator on some .glb/.gltf files: one JSON line per file with its issues, exit code 1 if
// any file has an error or a warning.  Run by tests/support/gltf_checks.py with the validator make installs:
//     NODE_PATH=.node/node_modules node tests/scripts/validate_gltf.js FILE...
const fs = require("fs");
const validator = require("gltf-validator");

async function main(files) {
    let bad = 0;
    for (const file of files) {
        const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {maxIssues: 100});
        const issues = report.issues;
        console.log(JSON.stringify({file: file, errors: issues.numErrors, warnings: issues.numWarnings,
                                    infos: issues.numInfos, messages: issues.messages}));
        if (issues.numErrors || issues.numWarnings) {
            bad += 1;
        }
    }
    return bad ? 1 : 0;
}

main(process.argv.slice(2)).then((status) => process.exit(status), (error) => {
    console.error(String(error));
    process.exit(2);
});
