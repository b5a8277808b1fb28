// A recorder of the parts of Flamenco's job-compiler API that job types use (author.Task,
// author.Command, task.addCommand, job.addTask, print, path), so that a job type's compileJob()
// can run in node.  Usage: node flamenco_author.js JOBTYPE.js SETTINGS.json -> JSON on stdout:
// {"label": ..., "tasks": [{"name", "type", "commands": [{"type", "parameters"}]}]}
"use strict";
const fs = require("fs");
const vm = require("vm");

const [jobTypeFile, settingsFile] = process.argv.slice(2);
const tasks = [];
const author = {
    Task(name, type) {
        const task = { name, type, commands: [], dependencies: [] };
        return {
            addCommand(cmd) { task.commands.push(cmd); },
            addDependency(other) { task.dependencies.push(other.name); },
            get name() { return task.name; },
            _record: task,
        };
    },
    Command(type, parameters) { return { type, parameters }; },
};
const userSettings = JSON.parse(fs.readFileSync(settingsFile, "utf8"));
const context = { author, path: require("path").posix, print: (...a) => console.error(...a) };
vm.createContext(context);
vm.runInContext(fs.readFileSync(jobTypeFile, "utf8") + "\nthis.JOB_TYPE = JOB_TYPE;", context);
// Defaults as the Manager fills them in before compiling.
const settings = {};
for (const s of context.JOB_TYPE.settings) {
    if (s.default !== undefined) settings[s.key] = s.default;
}
Object.assign(settings, userSettings);
for (const s of context.JOB_TYPE.settings) {
    if (s.required && (settings[s.key] === undefined || settings[s.key] === "")) {
        throw new Error("required setting missing: " + s.key);
    }
}
const job = { name: "test", settings, addTask(t) { tasks.push(t._record); } };
context.compileJob(job);
console.log(JSON.stringify({ label: context.JOB_TYPE.label, tasks }));
