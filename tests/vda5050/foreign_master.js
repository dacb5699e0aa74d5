#!/usr/bin/env node
// A foreign master control (vda-5050-lib's MasterController, VDA 5050 2.0.0) driving one of
// Fleet's robots in VDA 5050 mode (`fleet-agent --vda5050`), for the interop tests.
//
// Usage:
//   node foreign_master.js --broker mqtt://127.0.0.1:PORT --scenario FILE.json
//
// FILE.json: {"interface": "uagv", "manufacturer": "Fleet", "serial": "fl1", "map": "table_a",
//   "start": NODE, "middle": NODE, "pick": NODE, "drop": NODE} with NODE = {"id", "x", "y"[, "theta"]}:
//   where the robot stands, a road graph point on its way, the loading area to pick at and the
//   one to drop at.
//
// Steps, each printed as one JSON line on stdout ({"event": ...}):
//   online      the vehicle's connection is ONLINE (and its factsheet came)
//   base_end    order o1 released to `middle` only: the vehicle passes `middle` and stops there,
//               never reporting a node beyond the base
//   finished    the update releases pick and drop: the order is processed, both actions FINISHED
//   rejected    a lower orderUpdateId and a bad stitch (orderUpdateError), an unknown action
//               (orderError) and cancelOrder without an order (noOrderToCancel) each come back
//               as the specification's error in the vehicle's state
//   passed      all of the above; then every connection state change is printed
//   malformed_state  a state without its `errors` list (never expected)
//   fail        {"reason"}: a step failed or timed out; exit 1
"use strict";

const fs = require("fs");
const { MasterController, Topic } = require("vda-5050-lib");

function emit(obj) {
    process.stdout.write(JSON.stringify({ ts: new Date().toISOString(), ...obj }) + "\n");
}

function fail(reason) {
    emit({ event: "fail", reason });
    process.exit(1);
}

function parseArgs(argv) {
    const o = {};
    for (let i = 0; i < argv.length; i++) {
        const next = () => argv[++i];
        switch (argv[i]) {
            case "--broker": o.broker = next(); break;
            case "--scenario": o.scenario = next(); break;
            default: fail(`unknown argument ${argv[i]}`);
        }
    }
    if (!o.broker || !o.scenario) fail("usage: node foreign_master.js --broker URL --scenario FILE");
    return o;
}

const opts = parseArgs(process.argv.slice(2));
const scenario = JSON.parse(fs.readFileSync(opts.scenario, "utf8"));
const agv = { manufacturer: scenario.manufacturer, serialNumber: scenario.serial };

function node(spec, sequenceId, released, actions = []) {
    const position = { x: spec.x, y: spec.y, mapId: scenario.map };
    if (spec.theta !== undefined) position.theta = spec.theta;
    return { nodeId: spec.id, sequenceId, released, nodePosition: position, actions };
}

function edge(from, to, released) {
    return {
        edgeId: `${from.nodeId}-${to.nodeId}`, sequenceId: from.sequenceId + 1, released,
        startNodeId: from.nodeId, endNodeId: to.nodeId, actions: [],
    };
}

function order(orderId, orderUpdateId, nodes) {
    const edges = [];
    for (let i = 1; i < nodes.length; i++) edges.push(edge(nodes[i - 1], nodes[i], nodes[i].released));
    return { orderId, orderUpdateId, nodes, edges };
}

function action(actionId, actionType) {
    return {
        actionId, actionType, blockingType: "HARD",
        actionParameters: [{ key: "stationType", value: "floor" }, { key: "loadType", value: "EPAL" }],
    };
}

function within(ms, what, promise) {
    return Promise.race([promise, new Promise((_, reject) => setTimeout(() => reject(new Error(`${what}: no answer within ${ms} ms`)), ms))]);
}

let latestState;
const stateWaiters = [];
function onState(state) {
    if (!Array.isArray(state.errors)) emit({ event: "malformed_state", keys: Object.keys(state) });
    latestState = state;
    for (const w of stateWaiters.slice()) {
        if (w.test(state)) {
            stateWaiters.splice(stateWaiters.indexOf(w), 1);
            w.resolve(state);
        }
    }
}
function stateWhere(test) {
    if (latestState && test(latestState)) return Promise.resolve(latestState);
    return new Promise(resolve => stateWaiters.push({ test, resolve }));
}

async function main() {
    const master = new MasterController(
        { interfaceName: scenario.interface, transport: { brokerUrl: opts.broker }, vdaVersion: "2.0.0" },
        { targetAgvs: agv });
    let online;
    const isOnline = new Promise(resolve => { online = resolve; });
    master.trackAgvs((subject, state) => {
        if (subject.serialNumber !== scenario.serial) return;
        emit({ event: "connection", state });
        if (state === "ONLINE") online();
    });
    await master.start();
    let factsheet;
    const gotFactsheet = new Promise(resolve => { factsheet = resolve; });
    await master.subscribe("factsheet", agv, sheet => factsheet(sheet));
    await master.subscribe(Topic.State, agv, onState);
    await within(60000, "connection ONLINE", isOnline);
    const sheet = await within(10000, "factsheet", gotFactsheet);
    emit({ event: "online", speedMax: sheet.physicalParameters.speedMax });

    // The base ends at `middle`; pick and drop are horizon.
    const start = node(scenario.start, 0, true);
    const middle = node(scenario.middle, 2, true);
    const first = order("o1", 0, [start, middle, node(scenario.pick, 4, false), node(scenario.drop, 6, false)]);
    let beyondBase = false;
    await master.subscribe(Topic.State, agv, s => { if (s.orderId === "o1" && s.orderUpdateId === 0 && s.lastNodeSequenceId > 2) beyondBase = true; });
    let baseProcessed;
    const baseDone = new Promise(resolve => { baseProcessed = resolve; });
    await master.assignOrder(agv, first, {
        onOrderProcessed: (error, byCancelation, active) => baseProcessed({ error, active }),
        onNodeTraversed: n => emit({ event: "node", nodeId: n.nodeId, sequenceId: n.sequenceId }),
    });
    const base = await within(120000, "the base's end", baseDone);
    if (base.error) fail(`order o1 rejected: ${base.error.errorDescription}`);
    const standing = await within(30000, "standing at the base end",
        stateWhere(s => s.lastNodeId === scenario.middle.id && !s.driving));
    await new Promise(resolve => setTimeout(resolve, 2000));
    if (beyondBase || latestState.lastNodeSequenceId !== 2 || latestState.driving) {
        fail(`the vehicle went past its base: ${JSON.stringify(latestState.nodeStates)}`);
    }
    emit({ event: "base_end", lastNodeId: standing.lastNodeId, horizon: standing.nodeStates.filter(n => !n.released).length });

    // The update releases the rest: pick at `pick`, drop at `drop`.
    const update = order("o1", 1, [node(scenario.middle, 2, true), node(scenario.pick, 4, true, [action("pick-1", "pick")]),
        node(scenario.drop, 6, true, [action("drop-1", "drop")])]);
    const finished = {};
    let processed;
    const allDone = new Promise(resolve => { processed = resolve; });
    await master.assignOrder(agv, update, {
        onOrderProcessed: (error, byCancelation, active) => processed({ error, active }),
        onActionStateChanged: a => { finished[a.actionId] = a.actionStatus; emit({ event: "action", actionId: a.actionId, status: a.actionStatus }); },
        onNodeTraversed: n => emit({ event: "node", nodeId: n.nodeId, sequenceId: n.sequenceId }),
    });
    const done = await within(300000, "the transport", allDone);
    if (done.error) fail(`update rejected: ${done.error.errorDescription}`);
    if (finished["pick-1"] !== "FINISHED" || finished["drop-1"] !== "FINISHED") {
        fail(`actions not finished: ${JSON.stringify(finished)}`);
    }
    emit({ event: "finished", loads: latestState.loads.length, lastNodeId: latestState.lastNodeId });

    // Orders the vehicle must refuse, each with the specification's error.
    const dropNode = node(scenario.drop, 6, true);
    const refusals = [
        ["orderUpdateError", Topic.Order, order("o1", 0, [dropNode]), "orderUpdateId", "0"],
        ["orderUpdateError", Topic.Order, order("o1", 2, [node(scenario.pick, 4, true), dropNode]), "orderUpdateId", "2"],
        ["orderError", Topic.Order, order("o2", 0, [node(scenario.drop, 0, true), node(scenario.middle, 2, true, [action("beep-1", "beep")])]), "actionId", "beep-1"],
        ["noOrderToCancel", Topic.InstantActions, { instantActions: [{ actionId: "cancel-1", actionType: "cancelOrder", blockingType: "HARD" }] }, "actionId", "cancel-1"],
    ];
    const seen = [];
    for (const [type, topic, message, key, value] of refusals) {
        const matches = e => e.errorType === type && (e.errorReferences || []).some(r => r.referenceKey === key && r.referenceValue === value);
        const hasIt = s => s.errors.some(matches);
        await master.publish(topic, agv, message);
        const s = await within(10000, `${type} for ${key} ${value}`, stateWhere(hasIt));
        seen.push(s.errors.find(matches));
    }
    emit({ event: "rejected", errors: seen });
    emit({ event: "passed" });
}

main().catch(e => fail(e.message));
process.on("SIGTERM", () => process.exit(0));
