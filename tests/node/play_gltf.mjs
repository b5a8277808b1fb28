// Validates a GLB with Khronos' glTF validator and plays its animations in three.js (node, no
// browser), writing every mesh's world-space vertices (base + sum of weight * morph target,
// glTF's y-up axes) at each requested time as JSON.
// usage: node play_gltf.mjs file.glb times.json out.json   (times.json: {"times": [seconds...]})
import { readFileSync, writeFileSync } from "node:fs";
import validator from "gltf-validator";
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

const [glbPath, timesPath, outPath] = process.argv.slice(2);
const bytes = new Uint8Array(readFileSync(glbPath));
const times = JSON.parse(readFileSync(timesPath, "utf8")).times;

const report = await validator.validateBytes(bytes);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const gltf = await new Promise((resolve, reject) =>
  new GLTFLoader().parse(buffer, "", resolve, reject));

const scene = gltf.scene;
const mixer = new THREE.AnimationMixer(scene);
for (const clip of gltf.animations) {
  const action = mixer.clipAction(clip);
  action.setLoop(THREE.LoopOnce, 1);  // hold the last frame instead of wrapping to the first
  action.clampWhenFinished = true;
  action.play();
}

// The vertices three.js draws: base + sum_i influence_i * target_i (glTF morph targets are
// relative), then the mesh's world matrix.
function vertices(mesh) {
  const pos = mesh.geometry.attributes.position;
  const morphs = mesh.geometry.morphAttributes.position || [];
  const weights = mesh.morphTargetInfluences || [];
  const out = new Array(pos.count * 3);
  const v = new THREE.Vector3();
  for (let i = 0; i < pos.count; i++) {
    v.fromBufferAttribute(pos, i);
    morphs.forEach((m, k) => {
      if (!mesh.geometry.morphTargetsRelative) throw new Error("absolute morph targets");
      v.x += weights[k] * m.getX(i); v.y += weights[k] * m.getY(i); v.z += weights[k] * m.getZ(i);
    });
    v.applyMatrix4(mesh.matrixWorld);
    out[3 * i] = v.x; out[3 * i + 1] = v.y; out[3 * i + 2] = v.z;
  }
  return out;
}

const meshes = [];
scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
const frames = times.map((t) => {
  mixer.setTime(t);
  scene.updateMatrixWorld(true);
  return Object.fromEntries(meshes.map((m) => [m.name, vertices(m)]));
});
writeFileSync(outPath, JSON.stringify({
  validator: { errors: report.issues.numErrors, warnings: report.issues.numWarnings,
               messages: report.issues.messages.filter((m) => m.severity === 0) },
  animations: gltf.animations.map((c) => ({ name: c.name, duration: c.duration,
                                            tracks: c.tracks.map((t) => t.name) })),
  meshes: meshes.map((m) => ({ name: m.name, node: (m.parent && !m.parent.isScene ? m.parent.name : m.name),
                               morphs: (m.geometry.morphAttributes.position || []).length })),
  frames,
}));
