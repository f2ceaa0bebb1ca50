// Validates Kubernetes manifests against the API's JSON schemas (npm kubernetes-models,
// generated from the Kubernetes OpenAPI): types, required fields, enums and formats, offline.
// Usage: node tests/validate_k8s.mjs docker/k8s/*.yaml   (exit 1 on the first invalid object)
import { readFileSync } from "node:fs";
import { parseAllDocuments } from "yaml";
import * as apps from "kubernetes-models/apps/v1";
import * as core from "kubernetes-models/v1";
import * as autoscaling from "kubernetes-models/autoscaling/v2";
import * as policy from "kubernetes-models/policy/v1";

const models = {
  "apps/v1": apps,
  v1: core,
  "autoscaling/v2": autoscaling,
  "policy/v1": policy,
};

let failures = 0;
let checked = 0;
for (const file of process.argv.slice(2)) {
  for (const doc of parseAllDocuments(readFileSync(file, "utf8"))) {
    if (doc.errors.length) {
      console.error(`${file}: YAML error: ${doc.errors[0].message}`);
      failures++;
      continue;
    }
    const obj = doc.toJS();
    if (!obj) continue;
    const Model = models[obj.apiVersion]?.[obj.kind];
    if (!Model) {
      console.error(`${file}: no schema for ${obj.apiVersion} ${obj.kind}`);
      failures++;
      continue;
    }
    try {
      new Model(obj).validate();
      if (obj.kind === "ConfigMap") {
        for (const [key, text] of Object.entries(obj.data ?? {})) {
          if (key.endsWith(".yaml")) parseAllDocuments(text).forEach((d) => { if (d.errors.length) throw d.errors[0]; });
        }
      }
      checked++;
      console.log(`ok   ${file}: ${obj.kind} ${obj.metadata?.name}`);
    } catch (e) {
      console.error(`FAIL ${file}: ${obj.kind} ${obj.metadata?.name}: ${e.message}`);
      failures++;
    }
  }
}
console.log(`${checked} passed, ${failures} failed`);
process.exit(failures ? 1 : 0);
