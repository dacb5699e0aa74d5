#!/usr/bin/env node
// Virtual VDA 5050 (2.0.0) vehicles for the fleet's interop tests.
//
// Starts one vda-5050-lib AgvController + VirtualAgvAdapter per --vehicle in
// this process, all against one MQTT broker, and prints one JSON line per
// event on stdout (see `emit`). Events: started, ready, connection,
// order_received, order_accepted, order_rejected, node_reached,
// position_initialized, driving,
// action, error, error_cleared, base_done, order_done, stopping, stopped,
// fatal. Every line has "ts", "event" and (for vehicle events) "serial".
//
// Usage:
//   node virtual_agvs.js --broker mqtt://127.0.0.1:18830 --interface fleet \
//     --manufacturer Sim --vehicle AGV1,0,0,0,floor1 [--vehicle AGV2,0,5,0,floor1,n7] \
//     [--speed 1.0] [--reject-orders AGV2] [--no-route AGV3] \
//     [--state-interval MS] [--visualization-interval MS] [--time-lapse F] [--lost-position AGV1]
//
// --vehicle SERIAL,X,Y,THETA,MAPID[,LASTNODEID]   (THETA in rad, [-pi, pi];
//     LASTNODEID defaults to "" = "on no node yet")
// --reject-orders SERIAL  that vehicle rejects every order with an error of
//     errorType "orderError" (references topic, headerId, orderId, orderUpdateId)
// --no-route SERIAL       that vehicle rejects every order through the
//     adapter's public isRouteTraversable hook: errorType "noRouteError"
// --lost-position SERIAL  that vehicle starts not knowing where it is: positionInitialized
//     false at (0, 0) until a master tells it (initPosition)
//
// SIGTERM/SIGINT: every vehicle publishes connection OFFLINE (retained) and
// disconnects; exit 0. SIGKILL: the broker publishes each vehicle's last will,
// connection CONNECTIONBROKEN (retained, QoS 0), set by the lib at connect.
"use strict";

const {
    AgvController,
    VirtualAgvAdapter,
    ActionStatus,
    ErrorType,
} = require("vda-5050-lib");

function emit(obj) {
    // Node writes synchronously to files and pipes on Linux: one line per event, flushed.
    process.stdout.write(JSON.stringify({ ts: new Date().toISOString(), ...obj }) + "\n");
}

function usage(msg) {
    if (msg) {
        process.stderr.write(`virtual_agvs.js: ${msg}\n`);
    }
    process.stderr.write(
        "usage: node virtual_agvs.js --broker mqtt://127.0.0.1:PORT --interface NAME --manufacturer NAME\n" +
        "         --vehicle SERIAL,X,Y,THETA,MAPID[,LASTNODEID] [--vehicle ...] [--speed M_PER_S]\n" +
        "         [--reject-orders SERIAL]... [--no-route SERIAL]... [--state-interval MS]\n" +
        "         [--visualization-interval MS] [--time-lapse FACTOR] [--deviation-xy M]\n");
    process.exit(2);
}

function parseArgs(argv) {
    const opts = {
        broker: undefined,
        interfaceName: undefined,
        manufacturer: undefined,
        vehicles: [],
        speed: undefined,
        reject: new Set(),
        noRoute: new Set(),
        lostPosition: new Set(),
        stateInterval: undefined,
        visualizationInterval: undefined,
        timeLapse: undefined,
        deviationXy: undefined,
    };
    const num = (name, v) => {
        const n = Number(v);
        if (v === undefined || v === "" || !Number.isFinite(n)) {
            usage(`${name} needs a number, got ${v}`);
        }
        return n;
    };
    for (let i = 0; i < argv.length; i++) {
        const a = argv[i];
        const next = () => {
            if (i + 1 >= argv.length) {
                usage(`${a} needs a value`);
            }
            return argv[++i];
        };
        switch (a) {
            case "--broker": opts.broker = next(); break;
            case "--interface": opts.interfaceName = next(); break;
            case "--manufacturer": opts.manufacturer = next(); break;
            case "--speed": opts.speed = num(a, next()); break;
            case "--reject-orders": opts.reject.add(next()); break;
            case "--no-route": opts.noRoute.add(next()); break;
            case "--lost-position": opts.lostPosition.add(next()); break;
            case "--state-interval": opts.stateInterval = num(a, next()); break;
            case "--visualization-interval": opts.visualizationInterval = num(a, next()); break;
            case "--time-lapse": opts.timeLapse = num(a, next()); break;
            case "--deviation-xy": opts.deviationXy = num(a, next()); break;
            case "--vehicle": {
                const f = next().split(",");
                if (f.length < 5 || f.length > 6) {
                    usage(`--vehicle wants SERIAL,X,Y,THETA,MAPID[,LASTNODEID], got ${f.join(",")}`);
                }
                const v = {
                    serial: f[0],
                    x: num("x", f[1]),
                    y: num("y", f[2]),
                    theta: num("theta", f[3]),
                    mapId: f[4],
                    lastNodeId: f.length === 6 ? f[5] : "",
                };
                if (!/^[A-Za-z0-9_.:-]+$/.test(v.serial)) {
                    usage(`serial number ${v.serial} must be [A-Za-z0-9_.:-]+`);
                }
                if (Math.abs(v.theta) > Math.PI) {
                    usage(`theta ${v.theta} out of [-pi, pi] (the State schema would reject it)`);
                }
                if (!v.mapId) {
                    usage("empty MAPID");
                }
                opts.vehicles.push(v);
                break;
            }
            case "-h":
            case "--help": usage();
            // falls through (usage exits)
            default: usage(`unknown argument ${a}`);
        }
    }
    if (!opts.broker || opts.interfaceName === undefined || !opts.manufacturer || opts.vehicles.length === 0) {
        usage("--broker, --interface, --manufacturer and at least one --vehicle are required");
    }
    const serials = opts.vehicles.map(v => v.serial);
    if (new Set(serials).size !== serials.length) {
        usage("duplicate vehicle serial numbers");
    }
    for (const s of [...opts.reject, ...opts.noRoute, ...opts.lostPosition]) {
        if (!serials.includes(s)) {
            usage(`--reject-orders/--no-route/--lost-position ${s}: no such --vehicle`);
        }
    }
    return opts;
}

// Rejects every order through the adapter's public hook: the controller then
// reports errorType "noRouteError", description "order route is not traversable: ...".
class NoRouteVirtualAgvAdapter extends VirtualAgvAdapter {
    isRouteTraversable(context) {
        return [{
            referenceKey: AgvController.REF_KEY_ERROR_DESCRIPTION_DETAIL,
            referenceValue: "vehicle started with --no-route",
        }];
    }
}

const errorKey = e => JSON.stringify([e.errorType, e.errorLevel, e.errorDescription, e.errorReferences]);
const refsOf = e => Object.fromEntries((e.errorReferences || []).map(r => [r.referenceKey, r.referenceValue]));
const isOrderRejection = e => (e.errorReferences || []).some(r => r.referenceKey === "topic" && r.referenceValue === "order") &&
    !(e.errorReferences || []).some(r => r.referenceKey === "actionId");

// AgvController with event printing. The hooks whose names start with "_" are
// private in the lib's .d.ts (plain methods in its JS); pinned to vda-5050-lib 1.4.0.
class HarnessAgvController extends AgvController {
    constructor(agvId, clientOptions, controllerOptions, adapterOptions, harness) {
        super(agvId, clientOptions, controllerOptions, adapterOptions);
        this.harness = harness;
        this.seenErrors = new Set();
        this.seenActions = new Map(); // actionId -> status
        this.lastDriving = undefined;
        this.progressKey = undefined;
        this.isReady = false;
    }

    ev(event, fields) {
        emit({ event, serial: this.agvId.serialNumber, ...fields });
    }

    // Connection state of the MQTT client: online | offline.
    _emitConnectionStateChange(state) {
        const prev = this._connectionState;
        super._emitConnectionStateChange(state);
        if (this.harness && prev !== state) {
            this.ev("connection", { state });
        }
    }

    // Order subscription is made after the adapter has attached; "ready" = orders are received.
    async _subscribeOnStarted() {
        await super._subscribeOnStarted();
        this.isReady = true;
        const s = this._currentState;
        this.ev("ready", {
            lastNodeId: s.lastNodeId,
            agvPosition: s.agvPosition,
            orderTopic: this._subscriptionManager.getMqttTopic("order", this.agvId),
        });
    }

    _processOrder(order) {
        const nodes = Array.isArray(order && order.nodes) ? order.nodes : [];
        this.ev("order_received", {
            orderId: order && order.orderId,
            orderUpdateId: order && order.orderUpdateId,
            headerId: order && order.headerId,
            nodes: nodes.map(n => n && n.nodeId),
            released: nodes.filter(n => n && n.released).length,
        });
        if (this.harness.reject) {
            const error = this._createOrderError(order, ErrorType.Order,
                "order rejected: vehicle started with --reject-orders");
            // Keep one order rejection error (the latest), not one per order ever sent.
            this._updateState({
                errors: [...this._currentState.errors.filter(e => !isOrderRejection(e)), error],
            }, true);
            this.ev("order_rejected", { orderId: order && order.orderId, orderUpdateId: order && order.orderUpdateId,
                errorType: error.errorType, errorDescription: error.errorDescription, errorReferences: refsOf(error) });
            return;
        }
        const errorsBefore = new Set(this._currentState.errors.map(errorKey));
        super._processOrder(order);
        const added = this._currentState.errors.filter(e => !errorsBefore.has(errorKey(e)) && isOrderRejection(e));
        if (added.length > 0) {
            for (const e of added) {
                this.ev("order_rejected", { orderId: order && order.orderId, orderUpdateId: order && order.orderUpdateId,
                    errorType: e.errorType, errorDescription: e.errorDescription, errorReferences: refsOf(e) });
            }
        } else if (this.currentOrder && this.currentOrder.orderId === order.orderId &&
            this.currentOrder.orderUpdateId === order.orderUpdateId) {
            this.ev("order_accepted", { orderId: order.orderId, orderUpdateId: order.orderUpdateId });
        }
    }

    onStateChanged(changes) {
        if (!this.harness || !this.isReady) {
            return;
        }
        const s = this._currentState;
        if ("lastNodeId" in changes) {
            const p = s.agvPosition || {};
            // _processNode sets nodeStates + lastNodeId; the initPosition action only lastNodeId.
            this.ev("nodeStates" in changes ? "node_reached" : "position_initialized", {
                nodeId: s.lastNodeId,
                sequenceId: s.lastNodeSequenceId,
                orderId: s.orderId,
                orderUpdateId: s.orderUpdateId,
                x: p.x, y: p.y, theta: p.theta, mapId: p.mapId,
            });
        }
        if ("driving" in changes && changes.driving !== this.lastDriving) {
            this.lastDriving = changes.driving;
            this.ev("driving", { driving: changes.driving });
        }
        if ("actionStates" in changes) {
            for (const a of s.actionStates) {
                if (this.seenActions.get(a.actionId) !== a.actionStatus) {
                    this.seenActions.set(a.actionId, a.actionStatus);
                    this.ev("action", {
                        actionId: a.actionId, actionType: a.actionType, status: a.actionStatus,
                        resultDescription: a.resultDescription,
                        ...(a.actionType === "pick" || a.actionType === "drop" ? { loads: s.loads } : {}),
                    });
                }
            }
        }
        if ("errors" in changes) {
            const now = new Set();
            for (const e of s.errors) {
                const k = errorKey(e);
                now.add(k);
                if (!this.seenErrors.has(k)) {
                    this.ev("error", { errorType: e.errorType, errorLevel: e.errorLevel,
                        errorDescription: e.errorDescription, errorReferences: refsOf(e) });
                }
            }
            for (const k of this.seenErrors) {
                if (!now.has(k)) {
                    const [errorType, , errorDescription] = JSON.parse(k);
                    this.ev("error_cleared", { errorType, errorDescription });
                }
            }
            this.seenErrors = now;
        }
        this.checkProgress();
    }

    // base_done: all released nodes reached and their actions ended, horizon left;
    // order_done: nothing left at all. Emitted once per orderId/orderUpdateId.
    checkProgress() {
        const s = this._currentState;
        if (!this.currentOrder || s.orderId !== this.currentOrder.orderId) {
            return;
        }
        const pendingReleased = s.nodeStates.some(n => n.released) || s.edgeStates.some(e => e.released);
        const pendingActions = s.actionStates.some(a => !this.isInstantActionState(a) &&
            a.actionStatus !== ActionStatus.Finished && a.actionStatus !== ActionStatus.Failed);
        if (pendingReleased || pendingActions || s.driving) {
            return;
        }
        const kind = s.nodeStates.length > 0 || s.edgeStates.length > 0 ? "base_done" : "order_done";
        const key = `${kind}/${s.orderId}/${s.orderUpdateId}`;
        if (key === this.progressKey) {
            return;
        }
        this.progressKey = key;
        this.ev(kind, {
            orderId: s.orderId, orderUpdateId: s.orderUpdateId,
            lastNodeId: s.lastNodeId, lastNodeSequenceId: s.lastNodeSequenceId,
            horizonNodes: s.nodeStates.map(n => n.nodeId),
        });
    }
}

async function main() {
    const opts = parseArgs(process.argv.slice(2));
    const controllers = [];
    let stopping = false;

    const shutdown = async (signal) => {
        if (stopping) {
            return;
        }
        stopping = true;
        emit({ event: "stopping", signal });
        const timer = setTimeout(() => {
            emit({ event: "stopped", clean: false });
            process.exit(1);
        }, 5000);
        await Promise.allSettled(controllers.map(c => c.stop()));
        clearTimeout(timer);
        emit({ event: "stopped", clean: true });
        process.exit(0);
    };
    process.on("SIGTERM", () => shutdown("SIGTERM"));
    process.on("SIGINT", () => shutdown("SIGINT"));
    process.on("uncaughtException", err => {
        emit({ event: "fatal", error: String(err && err.stack || err) });
        process.exit(1);
    });
    process.on("unhandledRejection", err => {
        emit({ event: "fatal", error: String(err && err.stack || err) });
        process.exit(1);
    });

    emit({
        event: "started", pid: process.pid, broker: opts.broker, interfaceName: opts.interfaceName,
        manufacturer: opts.manufacturer, vdaVersion: "2.0.0",
        topicPrefix: `${opts.interfaceName}/v2/${opts.manufacturer}/`,
        vehicles: opts.vehicles.map(v => v.serial),
    });

    for (const v of opts.vehicles) {
        const agvId = { manufacturer: opts.manufacturer, serialNumber: v.serial };
        const clientOptions = {
            interfaceName: opts.interfaceName,
            transport: { brokerUrl: opts.broker },
            vdaVersion: "2.0.0",
        };
        const controllerOptions = {
            agvAdapterType: opts.noRoute.has(v.serial) ? NoRouteVirtualAgvAdapter : VirtualAgvAdapter,
        };
        if (opts.stateInterval !== undefined) {
            controllerOptions.publishStateInterval = opts.stateInterval;
        }
        if (opts.visualizationInterval !== undefined) {
            controllerOptions.publishVisualizationInterval = opts.visualizationInterval;
        }
        const adapterOptions = {
            initialPosition: { mapId: v.mapId, x: v.x, y: v.y, theta: v.theta, lastNodeId: v.lastNodeId },
        };
        if (opts.lostPosition.has(v.serial)) {
            adapterOptions.initialPosition = { mapId: v.mapId, x: 0, y: 0, theta: 0, lastNodeId: "", positionInitialized: false };
        }
        if (opts.speed !== undefined) {
            adapterOptions.vehicleSpeed = opts.speed;
        }
        if (opts.timeLapse !== undefined) {
            adapterOptions.timeLapse = opts.timeLapse;
        }
        if (opts.deviationXy !== undefined) {
            adapterOptions.agvNormalDeviationXyTolerance = opts.deviationXy;
        }
        const controller = new HarnessAgvController(agvId, clientOptions, controllerOptions, adapterOptions,
            { reject: opts.reject.has(v.serial) });
        controllers.push(controller);
        await controller.start();
    }
}

main().catch(err => {
    emit({ event: "fatal", error: String(err && err.stack || err) });
    process.exit(1);
});
