// SPDX-License-Identifier: GPL-3.0-or-later
//
// Flamenco job type: bake bdinterp in-betweens into every .blend of a shot list on shared
// storage, one task per file.  Each task runs examples/blender/bake_folder.py on its file through
// Flamenco's "blender-render" command (so the Worker's {blender} and {blenderArgs} apply):
//   {blender} {blenderArgs} <file.blend> --python <bake_folder.py> -- --count N ... --summary <json>
// A file's several-object characters (objects sharing a parent and a target key) are baked as
// one character each, as bake_folder.py bakes them.  bake_folder.py exits 1 when an object of the
// file failed, so Flamenco marks that task failed and the others go on.  Install: copy this file into the Manager's scripts/ folder and restart.

const JOB_TYPE = {
    label: "bdinterp Bake In-betweens",
    description: "Bake bounded-distortion in-betweens into each .blend (one task per file)",
    settings: [
        { key: "blendfiles", type: "string", required: true,
          description: "The .blend files on shared storage, separated by ';' or new lines" },
        { key: "script", type: "string", subtype: "file_path", required: true,
          description: "examples/blender/bake_folder.py on shared storage" },
        { key: "addon_dir", type: "string", subtype: "dir_path", default: "",
          description: "Folder holding the unpacked bdinterp_blender add-on (empty: the Worker's installed add-on)" },
        { key: "count", type: "int32", default: 8, description: "In-betweens per target key" },
        { key: "easing", type: "string", default: "LINEAR",
          choices: ["LINEAR", "EASE_IN", "EASE_OUT", "EASE_IN_OUT"], description: "Timing of the in-betweens" },
        { key: "skip_nonplanar", type: "bool", default: false,
          description: "Skip objects whose keys are not planar instead of failing the task" },
        { key: "summary_dir", type: "string", subtype: "dir_path", required: true,
          description: "Where each task writes <file>.bake_summary.json" },
        { key: "blender_cmd", type: "string", default: "{blender}", visible: "hidden" },
        { key: "blender_args", type: "string", default: "{blenderArgs}", visible: "hidden" },
    ],
};

function blendFiles(settings) {
    const files = String(settings.blendfiles).split(/[;\n]/).map((s) => s.trim()).filter((s) => s);
    if (files.length == 0) {
        throw "bdinterp: the job lists no .blend files";
    }
    for (const f of files) {
        if (!f.endsWith(".blend")) {
            throw `bdinterp: ${f} is not a .blend file`;
        }
    }
    return files;
}

function bakeArgs(settings, file) {
    let args = ["--python", settings.script, "--",
                "--count", String(settings.count), "--easing", settings.easing,
                "--summary", path.join(settings.summary_dir, path.basename(file) + ".bake_summary.json")];
    if (settings.addon_dir) {
        args = args.concat(["--addon", settings.addon_dir]);
    }
    if (settings.skip_nonplanar) {
        args.push("--skip-nonplanar");
    }
    return args;
}

function compileJob(job) {
    print("bdinterp bake job submitted");
    const settings = job.settings;
    for (const file of blendFiles(settings)) {
        const task = author.Task(`bake-${path.basename(file)}`, "blender");
        task.addCommand(author.Command("blender-render", {
            exe: settings.blender_cmd,
            exeArgs: settings.blender_args,
            argsBefore: [],
            blendfile: file,
            args: bakeArgs(settings, file),
        }));
        job.addTask(task);
    }
}
