#!/usr/bin/python3
"""A stand-in for VTube Studio's plugin API server (https://github.com/DenchiSoft/VTubeStudio), for the live
output's tests: it speaks the API's documented JSON over WebSocket (python3-websockets), checks each request's
shape and ranges, and logs every request and its verdict as a JSON line.

  vts_server.py --port-file P --log L [--token T] [--deny] [--parameters NAME,NAME,...]

It listens on 127.0.0.1 (a free port, written to P), issues token T on an AuthenticationTokenRequest (or, with
--deny, answers it as VTube Studio does when its user clicks Deny: APIError 50), authenticates an
AuthenticationRequest that carries it, and answers each InjectParameterDataRequest: InjectParameterDataResponse
when it is well formed and the session authenticated, APIError otherwise (453 when a parameter is not the
model's: the whole request fails, as VTube Studio's does). The model's parameters are --parameters (default:
every default parameter the face drives); InputParameterListRequest lists them as defaultParameters."""

import argparse
import asyncio
import json
import time

import websockets

# VTube Studio's default input parameters the face drives, and their documented ranges.
RANGES = {
    "MouthOpen": (0.0, 1.0), "MouthSmile": (0.0, 1.0),
    "FaceAngleX": (-30.0, 30.0), "FaceAngleY": (-30.0, 30.0), "FaceAngleZ": (-90.0, 90.0),
    "VoiceA": (0.0, 1.0), "VoiceI": (0.0, 1.0), "VoiceU": (0.0, 1.0), "VoiceE": (0.0, 1.0), "VoiceO": (0.0, 1.0),
}


def problems_of(request):
    """What is wrong with a request's envelope (the API's common fields), or []."""
    wrong = []
    if request.get("apiName") != "VTubeStudioPublicAPI":
        wrong.append("apiName")
    if request.get("apiVersion") != "1.0":
        wrong.append("apiVersion")
    if not isinstance(request.get("requestID"), str) or not request["requestID"]:
        wrong.append("requestID")
    if not isinstance(request.get("data"), dict):
        wrong.append("data")
    return wrong


def inject_problems(data, model):
    wrong = []
    if data.get("mode") not in ("set", "add"):
        wrong.append("mode")
    if not isinstance(data.get("faceFound"), bool):
        wrong.append("faceFound")
    values = data.get("parameterValues")
    if not isinstance(values, list) or not values:
        return wrong + ["parameterValues"]
    for value in values:
        name, number = value.get("id"), value.get("value")
        if name not in RANGES or name not in model:
            wrong.append("unknown parameter %r" % name)
        elif not isinstance(number, (int, float)) or not RANGES[name][0] <= number <= RANGES[name][1]:
            wrong.append("%s out of range: %r" % (name, number))
    return wrong


def reply(request, message_type, data):
    return json.dumps({"apiName": "VTubeStudioPublicAPI", "apiVersion": "1.0", "timestamp": int(time.time() * 1000),
                       "requestID": request.get("requestID", ""), "messageType": message_type, "data": data})


async def session(socket, options, log):
    authenticated = False
    async for text in socket:
        request = json.loads(text)
        kind = request.get("messageType")
        data = request.get("data") if isinstance(request.get("data"), dict) else {}
        wrong = problems_of(request)
        model = options.parameters.split(",") if options.parameters else list(RANGES)
        if kind == "AuthenticationTokenRequest":
            if not data.get("pluginName") or not data.get("pluginDeveloper"):
                wrong.append("plugin name or developer")
            answer = (reply(request, "APIError", {"errorID": 50, "message": "User has denied API access for your plugin."})
                      if options.deny else
                      reply(request, "AuthenticationTokenResponse", {"authenticationToken": options.token}))
        elif kind == "AuthenticationRequest":
            authenticated = not wrong and data.get("authenticationToken") == options.token
            answer = reply(request, "AuthenticationResponse", {
                "authenticated": authenticated,
                "reason": "Token valid." if authenticated else "Token invalid."})
        elif kind == "InjectParameterDataRequest":
            wrong += inject_problems(data, model)
            if not authenticated:
                wrong.append("not authenticated")
            answer = (reply(request, "InjectParameterDataResponse", {}) if not wrong else
                      reply(request, "APIError", {"errorID": 453, "message": "; ".join(wrong)}))
        elif kind == "InputParameterListRequest":
            if not authenticated:
                wrong.append("not authenticated")
            answer = reply(request, "InputParameterListResponse", {
                "modelLoaded": True, "modelName": "stand-in", "modelID": "stand-in", "customParameters": [],
                "defaultParameters": [{"name": name, "addedBy": "VTube Studio", "value": 0, "min": RANGES[name][0],
                                       "max": RANGES[name][1], "defaultValue": 0} for name in model]})
        else:
            wrong.append("unknown messageType %r" % kind)
            answer = reply(request, "APIError", {"errorID": 2, "message": "unknown messageType"})
        log.write(json.dumps({"time": time.time(), "type": kind, "problems": wrong, "request": request}) + "\n")
        log.flush()
        await socket.send(answer)


async def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--port-file", required=True)
    parser.add_argument("--port", type=int, default=0)
    parser.add_argument("--log", required=True)
    parser.add_argument("--token", default="talkinghead-test-token")
    parser.add_argument("--deny", action="store_true")
    parser.add_argument("--parameters", default="")
    options = parser.parse_args()
    with open(options.log, "a", encoding="utf-8") as log:
        async def handler(socket, path=None):
            try:
                await session(socket, options, log)
            except websockets.ConnectionClosed:
                pass
        async with websockets.serve(handler, "127.0.0.1", options.port) as server:
            port = server.sockets[0].getsockname()[1]
            with open(options.port_file, "w", encoding="utf-8") as out:
                out.write("%d\n" % port)
            await asyncio.Future()


if __name__ == "__main__":
    asyncio.run(main())
