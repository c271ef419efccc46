#!/usr/bin/python3
"""An independent MTConnect client (Python standard library: urllib, xml.etree) for the trueaxis
agent: polls /probe, /current and /sample and checks the documents against the structure the
MTConnect 1.3 standard defines (MTConnectDevices_1.3.xsd, MTConnectStreams_1.3.xsd,
MTConnectError_1.3.xsd: root element and namespace, Header attributes, Devices / Device /
DataItems / Components, Streams / DeviceStream / ComponentStream / Samples / Events / Condition),
sequence continuity between /sample requests, and the error documents.

usage: mtconnect_client.py URL check MACHINE[,MACHINE...]
       mtconnect_client.py URL unavailable DOWN_MACHINE UP_MACHINE
Prints one line per check; exit 0 when every check passed, 1 with the first failure.
"""
import sys
import time
import urllib.error
import urllib.request
import xml.etree.ElementTree as ET

DEVICES = "urn:mtconnect.org:MTConnectDevices:1.3"
STREAMS = "urn:mtconnect.org:MTConnectStreams:1.3"
ERROR = "urn:mtconnect.org:MTConnectError:1.3"
DEADLINE_S = 60


def q(ns, tag):
    return "{%s}%s" % (ns, tag)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def expect(cond, message):
    if not cond:
        fail(message)


def get(url, host=None):
    """(HTTP status, parsed root element, body)"""
    req = urllib.request.Request(url)
    if host:
        req.add_header("Host", host)
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            status, body = r.status, r.read()
            ctype = r.headers.get("Content-Type", "")
    except urllib.error.HTTPError as e:
        status, body, ctype = e.code, e.read(), e.headers.get("Content-Type", "")
    expect(ctype.startswith("text/xml"), "%s: Content-Type %r is not text/xml" % (url, ctype))
    return status, ET.fromstring(body), body


def header(root, ns, required):
    h = root.find(q(ns, "Header"))
    expect(h is not None, "%s has no Header" % root.tag)
    expect(list(root)[0] is h, "Header is not the first child of %s" % root.tag)
    for a in required:
        expect(a in h.attrib, "Header lacks %s" % a)
    expect(h.get("version", "").startswith("1.3"), "version %r is not 1.3" % h.get("version"))
    expect(int(h.get("instanceId")) >= 1, "instanceId < 1")
    return h


def streams_header(root):
    expect(root.tag == q(STREAMS, "MTConnectStreams"), "root %s is not MTConnectStreams" % root.tag)
    h = header(root, STREAMS, ["creationTime", "sender", "instanceId", "version", "bufferSize", "nextSequence",
                               "firstSequence", "lastSequence"])
    first, last, nxt = int(h.get("firstSequence")), int(h.get("lastSequence")), int(h.get("nextSequence"))
    expect(1 <= first <= last + 1, "firstSequence %d / lastSequence %d" % (first, last))
    expect(last - first + 1 <= int(h.get("bufferSize")), "more observations held than bufferSize")
    return h, first, last, nxt


def observations(root):
    """Every observation of a Streams document, checking the nesting on the way: (device, element, attrs, text)."""
    streams = root.find(q(STREAMS, "Streams"))
    expect(streams is not None, "no Streams")
    out = []
    for ds in streams:
        expect(ds.tag == q(STREAMS, "DeviceStream"), "%s inside Streams" % ds.tag)
        expect("name" in ds.attrib and "uuid" in ds.attrib, "DeviceStream without name / uuid")
        for cs in ds:
            expect(cs.tag == q(STREAMS, "ComponentStream"), "%s inside DeviceStream" % cs.tag)
            for a in ("component", "name", "componentId"):
                expect(a in cs.attrib, "ComponentStream lacks %s" % a)
            order = [c.tag for c in cs]
            allowed = [q(STREAMS, t) for t in ("Samples", "Events", "Condition")]
            expect(all(t in allowed for t in order), "ComponentStream holds %s" % order)
            expect(order == sorted(order, key=allowed.index) and len(set(order)) == len(order),
                   "Samples / Events / Condition out of order or repeated: %s" % order)
            for group in cs:
                expect(len(group) > 0, "an empty %s" % group.tag)
                for o in group:
                    for a in ("dataItemId", "timestamp", "sequence"):
                        expect(a in o.attrib, "%s lacks %s" % (o.tag, a))
                    if group.tag == q(STREAMS, "Condition"):
                        local = o.tag.split("}")[1]
                        expect(local in ("Normal", "Warning", "Fault", "Unavailable"), "condition %s" % local)
                        expect("type" in o.attrib, "condition without type")
                    out.append((ds.get("name"), o.tag, o.attrib, o.text))
    return out


def error_code(url, status, code):
    st, root, _ = get(url)
    expect(st == status, "%s: HTTP %d, expected %d" % (url, st, status))
    expect(root.tag == q(ERROR, "MTConnectError"), "%s: root %s is not MTConnectError" % (url, root.tag))
    header(root, ERROR, ["creationTime", "sender", "instanceId", "version", "bufferSize"])
    errors = root.findall(q(ERROR, "Errors") + "/" + q(ERROR, "Error"))
    expect(len(errors) == 1 and errors[0].get("errorCode") == code,
           "%s: errors %s, expected %s" % (url, [e.attrib for e in errors], code))
    return errors[0].text


def check(url, machines):
    # /probe: every machine a Device with the standard's data items.
    status, probe, _ = get(url + "/probe")
    expect(status == 200, "probe: HTTP %d" % status)
    expect(probe.tag == q(DEVICES, "MTConnectDevices"), "probe root %s" % probe.tag)
    header(probe, DEVICES, ["creationTime", "sender", "instanceId", "version", "bufferSize", "assetBufferSize", "assetCount"])
    devices = probe.findall(q(DEVICES, "Devices") + "/" + q(DEVICES, "Device"))
    expect(sorted(d.get("name") for d in devices) == sorted(machines),
           "devices %s, machines %s" % ([d.get("name") for d in devices], machines))
    ids = [e.get("id") for e in probe.iter() if "id" in e.attrib]
    expect(len(ids) == len(set(ids)), "ids are not unique")
    items = {}
    for d in devices:
        expect(d.get("uuid"), "Device %s without uuid" % d.get("name"))
        own = d.findall(q(DEVICES, "DataItems") + "/" + q(DEVICES, "DataItem"))
        expect(any(i.get("type") == "AVAILABILITY" and i.get("category") == "EVENT" for i in own), "no AVAILABILITY")
        expect(any(i.get("type") == "SYSTEM" and i.get("category") == "CONDITION" for i in own), "no SYSTEM condition")
        linear = d.findall(".//" + q(DEVICES, "Axes") + "/" + q(DEVICES, "Components") + "/" + q(DEVICES, "Linear"))
        expect(len(linear) >= 1, "%s: no Linear axis" % d.get("name"))
        for ax in linear:
            di = ax.findall(q(DEVICES, "DataItems") + "/" + q(DEVICES, "DataItem"))
            expect(any(i.get("type") == "POSITION" and i.get("subType") == "ACTUAL" and i.get("units") == "MILLIMETER"
                       and i.get("category") == "SAMPLE" for i in di), "axis %s: no POSITION ACTUAL MILLIMETER" % ax.get("name"))
            expect(any(i.get("type") == "x:COMPENSATION" and i.get("subType") == "ACTUAL" and i.get("units") == "MILLIMETER"
                       for i in di), "axis %s: no x:COMPENSATION" % ax.get("name"))
        sensors = d.findall(q(DEVICES, "Components") + "/" + q(DEVICES, "Sensor"))
        expect(len(sensors) >= 1, "%s: no temperature Sensor" % d.get("name"))
        for s in sensors:
            di = s.findall(q(DEVICES, "DataItems") + "/" + q(DEVICES, "DataItem"))
            expect(any(i.get("type") == "TEMPERATURE" and i.get("units") == "CELSIUS" and i.get("category") == "SAMPLE"
                       for i in di), "sensor %s: no TEMPERATURE CELSIUS" % s.get("name"))
        for i in d.iter(q(DEVICES, "DataItem")):
            items[i.get("id")] = i
    print("probe: %d devices, %d data items" % (len(devices), len(items)))

    # /current: every data item once, every machine AVAILABLE once its terminal answers.
    end = time.time() + DEADLINE_S
    while True:
        status, cur, _ = get(url + "/current")
        expect(status == 200, "current: HTTP %d" % status)
        h, first, last, nxt = streams_header(cur)
        obs = observations(cur)
        avail = {dev: text for dev, tag, a, text in obs if tag == q(STREAMS, "Availability")}
        positions = [text for dev, tag, a, text in obs if tag == q(STREAMS, "Position")]
        if all(avail.get(m) == "AVAILABLE" for m in machines) and all(p != "UNAVAILABLE" for p in positions):
            break
        expect(time.time() < end, "not every machine AVAILABLE: %s" % avail)
        time.sleep(0.2)
    expect(nxt == last + 1, "current: nextSequence %d after lastSequence %d" % (nxt, last))
    seen = [a["dataItemId"] for dev, tag, a, text in obs]
    expect(sorted(seen) == sorted(items), "current: %d of %d data items" % (len(set(seen)), len(items)))
    for dev, tag, a, text in obs:
        expect(1 <= int(a["sequence"]) <= last, "current: sequence %s outside the buffer" % a["sequence"])
        if tag in (q(STREAMS, "Position"), q(STREAMS, "Temperature")):
            float(text)
    print("current: %d observations, every machine AVAILABLE, sequences %d..%d" % (len(obs), first, last))

    # /sample continuity: nextSequence of one request is where the next one starts, nothing skipped.
    status, s1, _ = get(url + "/sample?from=%d&count=40" % first)
    expect(status == 200, "sample: HTTP %d" % status)
    _, f1, l1, n1 = streams_header(s1)
    seq1 = sorted(int(a["sequence"]) for _, _, a, _ in observations(s1))
    expect(seq1 == list(range(first, first + len(seq1))) and n1 == first + len(seq1) and len(seq1) == 40,
           "sample 1: sequences %s, nextSequence %d" % (seq1[:5], n1))
    time.sleep(0.5)
    status, s2, _ = get(url + "/sample?from=%d&count=%s" % (n1, h.get("bufferSize")))
    _, f2, l2, n2 = streams_header(s2)
    seq2 = sorted(int(a["sequence"]) for _, _, a, _ in observations(s2))
    expect(seq2 == list(range(n1, n2)) and n2 == l2 + 1, "sample 2 from %d: %s.. next %d last %d" % (n1, seq2[:3], n2, l2))
    status, s3, _ = get(url + "/sample?from=%d" % n2)
    _, _, l3, n3 = streams_header(s3)
    seq3 = sorted(int(a["sequence"]) for _, _, a, _ in observations(s3))
    expect(not seq3 or seq3[0] == n2, "sample 3 does not continue at %d: %s" % (n2, seq3[:3]))
    print("sample: %d + %d + %d observations, continuous from %d to %d" % (len(seq1), len(seq2), len(seq3), first, n3 - 1))

    # One device, and an XPath filter.
    one = machines[0]
    _, d1, _ = get(url + "/%s/current" % one)
    names = [ds.get("name") for ds in d1.find(q(STREAMS, "Streams"))]
    expect(names == [one], "/%s/current streams %s" % (one, names))
    _, p1, _ = get(url + "/current?path=//DataItem[@type=%22POSITION%22]")
    tags = {tag for _, tag, _, _ in observations(p1)}
    expect(tags == {q(STREAMS, "Position")}, "path=POSITION gives %s" % tags)
    print("device path and XPath filter: ok")

    # Errors: from beyond the buffer, count out of range, no device, bad number, another Host.
    status, cur, _ = get(url + "/current")
    _, first, last, nxt = streams_header(cur)
    error_code(url + "/sample?from=%d" % (nxt + 1000000), 400, "OUT_OF_RANGE")
    error_code(url + "/sample?count=0", 400, "OUT_OF_RANGE")
    error_code(url + "/current?at=%d" % (last + 1000), 400, "OUT_OF_RANGE")
    error_code(url + "/sample?from=abc", 400, "QUERY_ERROR")
    error_code(url + "/no-such-machine/current", 404, "NO_DEVICE")
    error_code(url + "/current?path=//DataItem[", 400, "INVALID_XPATH")
    status, root, _ = get(url + "/probe", host="attacker.example")
    expect(status == 403 and root.find(q(ERROR, "Errors") + "/" + q(ERROR, "Error")).get("errorCode") == "UNAUTHORIZED",
           "another Host: HTTP %d" % status)
    print("errors: OUT_OF_RANGE, QUERY_ERROR, NO_DEVICE, INVALID_XPATH, UNAUTHORIZED")

    # The buffer wraps: the oldest observations leave it, `from` before it is refused, and /current
    # still answers for every data item.
    end = time.time() + DEADLINE_S
    while first == 1:
        expect(time.time() < end, "the buffer did not wrap")
        time.sleep(0.3)
        _, cur, _ = get(url + "/current")
        _, first, last, nxt = streams_header(cur)
    error_code(url + "/sample?from=1", 400, "OUT_OF_RANGE")
    seen = [a["dataItemId"] for _, _, a, _ in observations(cur)]
    expect(sorted(seen) == sorted(items), "current after the wrap: %d of %d data items" % (len(seen), len(items)))
    # /current?at=lastSequence of that document: the same value of every data item, replayed from
    # the buffer's checkpoint (the state before firstSequence) and the observations up to `at`.
    now = {a["dataItemId"]: (a["sequence"], text) for _, _, a, text in observations(cur)}
    _, at, _ = get(url + "/current?at=%d" % last)
    _, _, _, at_next = streams_header(at)
    then = {a["dataItemId"]: (a["sequence"], text) for _, _, a, text in observations(at)}
    expect(at_next == last + 1 and then == now, "current?at=%d: nextSequence %d, %d of %d data items the same" %
           (last, at_next, sum(1 for k in now if then.get(k) == now[k]), len(now)))
    print("wrap: firstSequence %d, from=1 OUT_OF_RANGE, current and current?at still hold every data item" % first)


def unavailable(url, down, up):
    # The stopped terminal's machine: UNAVAILABLE at once, its values UNAVAILABLE, and its SYSTEM
    # condition a Fault once the compensator has seen the link fail (a cycle later); the other
    # machine AVAILABLE (a loaded computer may drop its link for a poll: it must be back in time).
    end = time.time() + DEADLINE_S
    while True:
        _, cur, _ = get(url + "/current")
        streams_header(cur)
        obs = observations(cur)
        avail = {dev: text for dev, tag, a, text in obs if tag == q(STREAMS, "Availability")}
        values = [(tag, text) for dev, tag, a, text in obs
                  if dev == down and tag in (q(STREAMS, "Position"), q(STREAMS, "Temperature"))]
        faults = [tag for dev, tag, a, text in obs if dev == down and a.get("type") == "SYSTEM"]
        state = (avail.get(down) == "UNAVAILABLE", avail.get(up) == "AVAILABLE",
                 bool(values) and all(text == "UNAVAILABLE" for _, text in values), faults == [q(STREAMS, "Fault")])
        if all(state):
            break
        expect(time.time() < end, "%s: availability %s, values %s, SYSTEM %s (down, up, values, fault: %s)" %
               (down, avail, values[:3], faults, state))
        time.sleep(0.2)
    print("%s UNAVAILABLE (positions and temperatures too, SYSTEM Fault), %s AVAILABLE" % (down, up))


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[2] == "check":
        check(sys.argv[1], sys.argv[3].split(","))
    elif len(sys.argv) == 5 and sys.argv[2] == "unavailable":
        unavailable(sys.argv[1], sys.argv[3], sys.argv[4])
    else:
        fail(__doc__)
    print("ok")
