// Decodes a file of MAVLink 2 frames with node-mavlink (an implementation independent of ours):
// prints {packets: [...], invalid: N} as JSON. Used by avoid_test.cpp; `npm install` here first
// (cmake/setup.sh test does it).
const { MavLinkPacketSplitter, MavLinkPacketParser, minimal, common } = require('node-mavlink')
const fs = require('fs')
const { Readable } = require('stream')
const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY }
const splitter = new MavLinkPacketSplitter()
const out = []
Readable.from([fs.readFileSync(process.argv[2])]).pipe(splitter).pipe(new MavLinkPacketParser())
  .on('data', p => {
    const clazz = REGISTRY[p.header.msgid]
    const d = p.protocol.data(p.payload, clazz)
    const o = { msgid: p.header.msgid, seq: p.header.seq, sysid: p.header.sysid, compid: p.header.compid, crc: p.crc }
    for (const k of Object.keys(d)) o[k] = typeof d[k] === 'bigint' ? Number(d[k]) : d[k]
    out.push(o)
  })
  .on('end', () => { console.log(JSON.stringify({ packets: out, invalid: splitter.invalidPackages || 0, unknown: splitter.unknownPackagesCount || 0 })) })
