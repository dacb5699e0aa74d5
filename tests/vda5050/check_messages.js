#!/usr/bin/env node
// Listens on an MQTT broker and checks every VDA 5050 message a master publishes (order,
// instantActions by default) against
//   (a) vda-5050-lib 1.4.0's 2.0 validators (what the lib's vehicles accept),
//   (b) with --schemas, the official JSON schema of the message's `version`
//       (DIR/<version>/json_schemas/<name>.schema, compiled with ajv + ajv-formats),
//   (c) the order rules a master must keep, per (manufacturer/serial, orderId).
//
// Usage:
//   node check_messages.js --broker mqtt://127.0.0.1:18830 [--schemas DIR_OF_VERSION_FOLDERS]
//     [--topics order,instantActions] [--out FILE]
//
// Topics checked: {interface}/v{major}/{manufacturer}/{serial}/{name} with name in --topics;
// everything else on `#` is ignored (not counted). Prints "ready" on stderr once subscribed.
// On SIGTERM/SIGINT prints ONE JSON line on stdout (also written to --out FILE):
//   {"checked":N,"by_topic":{name:n},"invalid":[{topic,reason}] (first 20),"invalid_count":K,
//    "schemas":"official+lib"|"lib"}
// and exits 0 when invalid_count == 0 and checked > 0, else 1 (2 on usage / schema load errors).
//
// Rules (c), per (manufacturer/serial, orderId), compared with the previous *valid* message of that
// order (an invalid message would be rejected by the vehicle, so it does not move the reference):
//   - orderUpdateId strictly increases;
//   - an update's first node equals the previous message's last released node (nodeId and
//     sequenceId);
//   - node sequenceIds even and +2 each, edge sequenceIds odd and +2 each; edges = nodes - 1,
//     edge[i].sequenceId = node[i].sequenceId + 1, startNodeId/endNodeId = the neighbour nodes;
//   - first node released; released nodes (and edges) come before horizon ones.
// Also: the payload's version major must match the topic's v{major}, manufacturer/serialNumber
// must match the topic, and version must be "2.0.0"/"2.1.0" (lib only) or one of DIR's folders.
"use strict";

const fs = require("fs");
const path = require("path");
const mqtt = require("mqtt");
const libValidators = require("vda-5050-lib/common/vda-5050-validators-2.0");

const MAX_LISTED = 20;

function usage(msg) {
    if (msg) {
        process.stderr.write(`check_messages.js: ${msg}\n`);
    }
    process.stderr.write(
        "usage: node check_messages.js --broker mqtt://HOST:PORT [--schemas DIR_OF_VERSION_FOLDERS]\n" +
        "         [--topics order,instantActions] [--out FILE]\n");
    process.exit(2);
}

function parseArgs(argv) {
    const o = { topics: ["order", "instantActions"] };
    for (let i = 0; i < argv.length; i++) {
        const a = argv[i];
        const next = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
        switch (a) {
            case "--broker": o.broker = next(); break;
            case "--schemas": o.schemas = next(); break;
            case "--topics": o.topics = next().split(",").map(s => s.trim()).filter(Boolean); break;
            case "--out": o.out = next(); break;
            case "-h": case "--help": usage(); break;
            default: usage(`unknown argument ${a}`);
        }
    }
    if (!o.broker) {
        usage("--broker is required");
    }
    if (o.topics.length === 0) {
        usage("--topics is empty");
    }
    return o;
}

// ---------------------------------------------------------------------------------------------
// lib validators (2.0)

const LIB_VALIDATOR = {
    order: "validateOrder",
    instantActions: "validateInstantActions",
    state: "validateState",
    connection: "validateConnection",
    visualization: "validateVisualization",
    factsheet: "validateFactsheet",
};

function libErrors(name, msg) {
    const fnName = LIB_VALIDATOR[name];
    const fn = fnName && libValidators[fnName];
    if (!fn) {
        return [`lib: no 2.0 validator for topic ${name}`];
    }
    if (fn(msg)) {
        return [];
    }
    return (fn.errors || [{}]).slice(0, 3).map(e =>
        `lib: ${e.instanceLocation || "?"} fails ${e.keywordLocation || "?"}`);
}

// ---------------------------------------------------------------------------------------------
// official schemas (ajv)

// Removes commas directly before } or ] (outside strings), e.g. 2.0.0/state.schema.
function mendTrailingCommas(text) {
    let out = "";
    let inString = false;
    for (let i = 0; i < text.length; i++) {
        const c = text[i];
        if (inString) {
            out += c;
            if (c === "\\") {
                out += text[++i] ?? "";
            } else if (c === "\"") {
                inString = false;
            }
            continue;
        }
        if (c === "\"") {
            inString = true;
        } else if (c === ",") {
            let j = i + 1;
            while (j < text.length && /\s/.test(text[j])) {
                j++;
            }
            if (text[j] === "}" || text[j] === "]") {
                continue;  // drop it
            }
        }
        out += c;
    }
    return out;
}

// draft-04 → draft-07 shape: id → $id, boolean exclusiveMinimum/Maximum → numeric.
function upgradeDraft04(node) {
    if (Array.isArray(node)) {
        node.forEach(upgradeDraft04);
        return;
    }
    if (!node || typeof node !== "object") {
        return;
    }
    if (typeof node.id === "string" && node.$id === undefined) {
        node.$id = node.id;
        delete node.id;
    }
    for (const [bool, num] of [["exclusiveMinimum", "minimum"], ["exclusiveMaximum", "maximum"]]) {
        if (typeof node[bool] === "boolean") {
            if (node[bool] && typeof node[num] === "number") {
                node[bool] = node[num];
                delete node[num];
            } else {
                delete node[bool];
            }
        }
    }
    Object.values(node).forEach(upgradeDraft04);
}

function makeAjv(kind) {
    const addFormats = require("ajv-formats");
    let Cls;
    if (kind === "2020-12") {
        Cls = require("ajv/dist/2020");
    } else if (kind === "2019-09") {
        Cls = require("ajv/dist/2019");
    } else {
        Cls = require("ajv");  // draft-07 (draft-06 and upgraded draft-04 compile here too)
    }
    Cls = Cls.default || Cls;
    // strict: false: the official schemas carry non-standard keywords ("subtopic").
    const ajv = new Cls({ allErrors: true, strict: false });
    addFormats(ajv);
    return ajv;
}

function schemaDialect(schema) {
    const s = typeof schema.$schema === "string" ? schema.$schema : "";
    if (s.includes("2020-12")) return "2020-12";
    if (s.includes("2019-09")) return "2019-09";
    if (s.includes("draft-04")) return "draft-04";
    return "draft-07";  // draft-07, draft-06 or unspecified
}

// Returns Map version -> Map name -> {validate} | {error}
function loadOfficialSchemas(dir, names) {
    const ajvs = {};
    const result = new Map();
    let versions;
    try {
        versions = fs.readdirSync(dir, { withFileTypes: true })
            .filter(d => d.isDirectory() && fs.existsSync(path.join(dir, d.name, "json_schemas")))
            .map(d => d.name).sort();
    } catch (e) {
        usage(`cannot read --schemas ${dir}: ${e.message}`);
    }
    if (versions.length === 0) {
        usage(`--schemas ${dir} has no <version>/json_schemas folders`);
    }
    const loaded = [];
    for (const version of versions) {
        const perName = new Map();
        result.set(version, perName);
        for (const name of names) {
            const base = path.join(dir, version, "json_schemas", name);
            const file = [`${base}.schema`, `${base}.json`].find(f => fs.existsSync(f));
            if (!file) {
                perName.set(name, { error: `no official ${version} schema for ${name}` });
                continue;
            }
            let schema;
            try {
                schema = JSON.parse(mendTrailingCommas(fs.readFileSync(file, "utf8")));
            } catch (e) {
                usage(`cannot parse ${file}: ${e.message}`);
            }
            const dialect = schemaDialect(schema);
            let kind = dialect;
            if (kind === "draft-04") {
                delete schema.$schema;
                upgradeDraft04(schema);
                kind = "draft-07";
            }
            delete schema.$id;  // same $id in several versions would clash in one ajv instance
            ajvs[kind] = ajvs[kind] || makeAjv(kind);
            try {
                perName.set(name, { validate: ajvs[kind].compile(schema) });
            } catch (e) {
                usage(`cannot compile ${file}: ${e.message}`);
            }
            loaded.push(`${version}/${path.basename(file)} (${dialect})`);
        }
    }
    process.stderr.write(`check_messages.js: official schemas: ${loaded.join(", ")}\n`);
    return result;
}

function officialErrors(official, version, name, msg) {
    const perName = official.get(version);
    if (!perName) {
        return [`unknown version ${JSON.stringify(version)}`];
    }
    const entry = perName.get(name);
    if (entry.error) {
        return [entry.error];
    }
    if (entry.validate(msg)) {
        return [];
    }
    return entry.validate.errors.slice(0, 3).map(e =>
        `official ${version}: ${e.instancePath || "/"} ${e.message}` +
        (e.params && e.params.missingProperty ? "" : ` (${e.schemaPath})`));
}

// ---------------------------------------------------------------------------------------------
// order rules

const orders = new Map();  // `${manufacturer}/${serial}` + "\0" + orderId -> last valid order

function lastReleasedNode(order) {
    let last;
    for (const n of order.nodes) {
        if (n.released === true) {
            last = n;
        }
    }
    return last;
}

function orderRuleErrors(agvKey, msg) {
    const errs = [];
    const nodes = msg.nodes;
    const edges = msg.edges;
    if (!Array.isArray(nodes) || !Array.isArray(edges) || typeof msg.orderId !== "string" ||
        !Number.isInteger(msg.orderUpdateId)) {
        return errs;  // the schema checks already report this
    }
    const id = `order ${msg.orderId}/${msg.orderUpdateId}`;
    if (nodes.length === 0) {
        errs.push(`${id}: no nodes`);
        return errs;
    }
    const seqOk = (s) => Number.isInteger(s);
    nodes.forEach((n, i) => {
        if (!seqOk(n.sequenceId)) return;
        if (n.sequenceId % 2 !== 0) {
            errs.push(`${id}: node ${n.nodeId} sequenceId ${n.sequenceId} is odd`);
        }
        if (i > 0 && seqOk(nodes[i - 1].sequenceId) && n.sequenceId !== nodes[i - 1].sequenceId + 2) {
            errs.push(`${id}: node ${n.nodeId} sequenceId ${n.sequenceId} is not previous node's + 2`);
        }
    });
    edges.forEach((e, i) => {
        if (!seqOk(e.sequenceId)) return;
        if (e.sequenceId % 2 !== 1) {
            errs.push(`${id}: edge ${e.edgeId} sequenceId ${e.sequenceId} is even`);
        }
        if (i > 0 && seqOk(edges[i - 1].sequenceId) && e.sequenceId !== edges[i - 1].sequenceId + 2) {
            errs.push(`${id}: edge ${e.edgeId} sequenceId ${e.sequenceId} is not previous edge's + 2`);
        }
    });
    if (edges.length !== nodes.length - 1) {
        errs.push(`${id}: ${edges.length} edges for ${nodes.length} nodes`);
    } else {
        edges.forEach((e, i) => {
            const a = nodes[i], b = nodes[i + 1];
            if (seqOk(e.sequenceId) && seqOk(a.sequenceId) && e.sequenceId !== a.sequenceId + 1) {
                errs.push(`${id}: edge ${e.edgeId} sequenceId ${e.sequenceId} not between nodes ` +
                    `${a.sequenceId} and ${b.sequenceId}`);
            }
            if (e.startNodeId !== a.nodeId || e.endNodeId !== b.nodeId) {
                errs.push(`${id}: edge ${e.edgeId} ${e.startNodeId}->${e.endNodeId} does not join ` +
                    `${a.nodeId}->${b.nodeId}`);
            }
        });
    }
    if (nodes[0].released !== true) {
        errs.push(`${id}: first node ${nodes[0].nodeId} not released`);
    }
    const prefix = (list, kind, idKey) => {
        let horizonSeen;
        for (const x of list) {
            if (x.released === true && horizonSeen) {
                errs.push(`${id}: released ${kind} ${x[idKey]} after horizon ${kind} ${horizonSeen}`);
                return;
            }
            if (x.released !== true && !horizonSeen) {
                horizonSeen = x[idKey];
            }
        }
    };
    prefix(nodes, "node", "nodeId");
    prefix(edges, "edge", "edgeId");

    const prev = orders.get(`${agvKey}\0${msg.orderId}`);
    if (prev) {
        if (!(msg.orderUpdateId > prev.orderUpdateId)) {
            errs.push(`${id}: orderUpdateId ${msg.orderUpdateId} not above previous ${prev.orderUpdateId}`);
        }
        const base = lastReleasedNode(prev);
        const first = nodes[0];
        if (base && (first.nodeId !== base.nodeId || first.sequenceId !== base.sequenceId)) {
            errs.push(`${id}: first node ${first.nodeId}/${first.sequenceId} does not stitch to ` +
                `previous base end ${base.nodeId}/${base.sequenceId} (update ${prev.orderUpdateId})`);
        }
    }
    return errs;
}

// ---------------------------------------------------------------------------------------------

function main() {
    const opts = parseArgs(process.argv.slice(2));
    const official = opts.schemas ? loadOfficialSchemas(opts.schemas, opts.topics) : null;
    const knownVersions = official ? [...official.keys()] : ["2.0.0", "2.1.0"];
    const wanted = new Set(opts.topics);

    let checked = 0;
    let invalidCount = 0;
    const byTopic = {};
    const invalid = [];

    const check = (topic, payload) => {
        const parts = topic.split("/");
        if (parts.length < 5) return;
        const [major, manufacturer, serial, name] = parts.slice(-4);
        if (!wanted.has(name) || !/^v\d+$/.test(major)) return;
        checked++;
        byTopic[name] = (byTopic[name] || 0) + 1;

        let errs = [];
        let msg;
        try {
            msg = JSON.parse(payload.toString("utf8"));
        } catch (e) {
            errs.push(`not JSON: ${e.message}`);
        }
        if (msg !== undefined && (msg === null || typeof msg !== "object" || Array.isArray(msg))) {
            errs.push("payload is not a JSON object");
            msg = undefined;
        }
        if (msg) {
            const version = msg.version;
            if (!knownVersions.includes(version)) {
                errs.push(`unknown version ${JSON.stringify(version)}`);
            } else if (`v${version.split(".")[0]}` !== major) {
                errs.push(`version ${version} on a ${major} topic`);
            }
            if (msg.manufacturer !== manufacturer || msg.serialNumber !== serial) {
                errs.push(`manufacturer/serialNumber ${msg.manufacturer}/${msg.serialNumber} ` +
                    `do not match the topic`);
            }
            errs.push(...libErrors(name, msg));
            if (official && knownVersions.includes(version)) {
                errs.push(...officialErrors(official, version, name, msg));
            }
            if (name === "order") {
                const agvKey = `${manufacturer}/${serial}`;
                errs.push(...orderRuleErrors(agvKey, msg));
                if (errs.length === 0) {
                    orders.set(`${agvKey}\0${msg.orderId}`, msg);
                }
            }
        }
        if (errs.length > 0) {
            invalidCount++;
            const reason = errs.join("; ");
            if (invalid.length < MAX_LISTED) {
                invalid.push({ topic, reason });
            }
            process.stderr.write(`check_messages.js: INVALID ${topic}: ${reason}\n`);
        }
    };

    const client = mqtt.connect(opts.broker, {
        clientId: `check_messages_${process.pid}_${Math.random().toString(16).slice(2, 8)}`,
        clean: true,
        reconnectPeriod: 1000,
    });
    client.on("error", e => process.stderr.write(`check_messages.js: mqtt error: ${e.message}\n`));
    client.on("message", (topic, payload) => {
        try {
            check(topic, payload);
        } catch (e) {
            process.stderr.write(`check_messages.js: internal error on ${topic}: ${e.stack}\n`);
        }
    });
    let subscribed = false;
    client.on("connect", () => {
        client.subscribe("#", { qos: 1 }, (err, granted) => {
            if (err || !granted || granted.some(g => g.qos === 128)) {
                process.stderr.write(`check_messages.js: subscribe failed: ${err ? err.message : "refused"}\n`);
                return;
            }
            if (!subscribed) {
                subscribed = true;
                process.stderr.write("ready\n");
            }
        });
    });

    let finished = false;
    const finish = () => {
        if (finished) return;
        finished = true;
        const summary = {
            checked,
            by_topic: byTopic,
            invalid,
            invalid_count: invalidCount,
            schemas: official ? "official+lib" : "lib",
        };
        const line = JSON.stringify(summary);
        const code = invalidCount === 0 && checked > 0 ? 0 : 1;
        if (opts.out) {
            try {
                fs.writeFileSync(opts.out, line + "\n");
            } catch (e) {
                process.stderr.write(`check_messages.js: cannot write ${opts.out}: ${e.message}\n`);
            }
        }
        client.end(true);
        process.stdout.write(line + "\n", () => process.exit(code));
    };
    process.on("SIGTERM", finish);
    process.on("SIGINT", finish);
}

main();
