// SPDX-License-Identifier: Apache-2.0
//! roz-mcap-strict FILE... [--cut FILE...]
//!
//! Reads each MCAP file with the `mcap` crate's linear reader, strictly
//! (magic at both ends and nothing after, every chunk's CRC, the data and
//! summary sections' CRCs, no record past 16 MiB), then checks what its
//! readers leave to the writer: a footer of the specification's 20 bytes,
//! the summary's statistics against the messages read, every chunk index
//! against its chunk, every message index entry against the message it
//! points to, the summary offsets against their groups, and no two chunks
//! overlapping in log time. A file after `--cut` is a recording whose writer
//! died: it has no end, and every complete chunk before the cut must be
//! readable as above. One line per file; exit 1 on the first problem.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::process::ExitCode;

use mcap::records::{ChunkHeader, ChunkIndex, Record, Statistics, SummaryOffset};
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

/// The largest record, and chunk once decompressed, taken (ROZ_MCAP_MAX_RECORD).
const LIMIT: usize = 16 << 20;

type Res<T> = Result<T, String>;

struct Chunk {
    offset: u64,
    length: u64, // the whole record, opcode and length included
    header: ChunkHeader,
    /// (offset in the decompressed records, channel, log time) of each message
    messages: Vec<(u64, u16, u64)>,
}

#[derive(Default)]
struct File {
    chunks: Vec<Chunk>,
    top: Vec<(u64, u8)>, // every top-level record: offset, opcode
    chunk_indexes: Vec<ChunkIndex>,
    message_indexes: BTreeMap<u64, Vec<(u16, Vec<(u64, u64)>)>>, // by offset of the chunk before
    stats: Option<Statistics>,
    summary_offsets: Vec<SummaryOffset>,
    footer_at: Option<u64>,
    data_end_at: Option<u64>,
    per_channel: BTreeMap<u16, u64>,
    channels: BTreeMap<u16, u16>, // id -> schema id
    schemas: usize,
    messages: u64,
    first: Option<u64>,
    last: Option<u64>,
}

/// A chunk's records, decompressed (bounded by LIMIT before allocating).
fn chunk_records<'a>(h: &ChunkHeader, data: &'a [u8], at: u64) -> Res<Cow<'a, [u8]>> {
    if h.uncompressed_size as usize > LIMIT {
        return Err(format!("chunk at offset {at}: {} bytes uncompressed, past {LIMIT}",
                           h.uncompressed_size));
    }
    match h.compression.as_str() {
        "" => Ok(Cow::Borrowed(data)),
        "zstd" => zstd::bulk::decompress(data, h.uncompressed_size as usize)
            .map(Cow::Owned)
            .map_err(|e| format!("chunk at offset {at}: zstd: {e}")),
        other => Err(format!("chunk at offset {at}: compression {other:?} is not one roz writes")),
    }
}

impl File {
    fn message(&mut self, channel: u16, log_time: u64, at: &str) -> Res<()> {
        if !self.channels.contains_key(&channel) {
            return Err(format!("{at}: a message on channel {channel} before its channel record"));
        }
        *self.per_channel.entry(channel).or_default() += 1;
        self.messages += 1;
        self.first = Some(self.first.map_or(log_time, |f| f.min(log_time)));
        self.last = Some(self.last.map_or(log_time, |l| l.max(log_time)));
        Ok(())
    }

    fn top_record(&mut self, opcode: u8, data: &[u8], offset: u64, summary: bool) -> Res<()> {
        self.top.push((offset, opcode));
        let rec = mcap::parse_record(opcode, data)
            .map_err(|e| format!("record at offset {offset} (opcode {opcode:#04x}): {e}"))?;
        match rec {
            Record::Footer(_) => {
                if data.len() != 20 {
                    return Err(format!("footer at offset {offset}: {} bytes, the specification's \
                                        is 20", data.len()));
                }
                self.footer_at = Some(offset);
            }
            Record::Schema { header, .. } if !summary => {
                if header.id == 0 {
                    return Err(format!("schema at offset {offset}: id 0 is reserved"));
                }
                self.schemas += 1;
            }
            Record::Channel(c) if !summary => {
                self.channels.insert(c.id, c.schema_id);
            }
            Record::Message { .. } => {
                return Err(format!("message at offset {offset} outside a chunk"));
            }
            Record::Chunk { header, data } => {
                let records = chunk_records(&header, &data, offset)?;
                if records.len() as u64 != header.uncompressed_size {
                    return Err(format!("chunk at offset {offset}: {} bytes of records, its \
                                        header says {}", records.len(), header.uncompressed_size));
                }
                let crc = crc32fast::hash(&records);
                if header.uncompressed_crc != 0 && crc != header.uncompressed_crc {
                    return Err(format!("chunk at offset {offset}: CRC {crc:08x}, its header \
                                        says {:08x}", header.uncompressed_crc));
                }
                let mut messages = Vec::new();
                let mut at = 0usize;
                while at < records.len() {
                    if records.len() - at < 9 {
                        return Err(format!("chunk at offset {offset}: a record cut short"));
                    }
                    let op = records[at];
                    let n = u64::from_le_bytes(records[at + 1..at + 9].try_into().unwrap());
                    if n > (records.len() - at - 9) as u64 {
                        return Err(format!("chunk at offset {offset}: a record runs past its end"));
                    }
                    let body = &records[at + 9..at + 9 + n as usize];
                    let where_ = format!("chunk at offset {offset}, record at {at}");
                    match mcap::parse_record(op, body).map_err(|e| format!("{where_}: {e}"))? {
                        Record::Message { header: m, .. } => {
                            if m.log_time < header.message_start_time
                                || m.log_time > header.message_end_time
                            {
                                return Err(format!("{where_}: log time {} outside the chunk's \
                                                    {}..{}", m.log_time,
                                                   header.message_start_time,
                                                   header.message_end_time));
                            }
                            self.message(m.channel_id, m.log_time, &where_)?;
                            messages.push((at as u64, m.channel_id, m.log_time));
                        }
                        Record::Channel(c) => {
                            self.channels.insert(c.id, c.schema_id);
                        }
                        Record::Schema { .. } => self.schemas += 1,
                        _ => return Err(format!("{where_}: opcode {op:#04x} inside a chunk")),
                    }
                    at += 9 + n as usize;
                }
                self.chunks.push(Chunk { offset, length: 9 + data.len() as u64 + 8 * 3 + 4 +
                                             4 + header.compression.len() as u64 + 8,
                                         header, messages });
            }
            Record::MessageIndex(mi) => {
                let chunk = self.chunks.last().map(|c| c.offset)
                    .ok_or(format!("message index at offset {offset} before any chunk"))?;
                let entries = mi.records.iter().map(|e| (e.log_time, e.offset)).collect();
                self.message_indexes.entry(chunk).or_default().push((mi.channel_id, entries));
            }
            Record::ChunkIndex(ci) => self.chunk_indexes.push(ci),
            Record::Statistics(s) => {
                if self.stats.replace(s).is_some() {
                    return Err("two statistics records".into());
                }
            }
            Record::SummaryOffset(so) => self.summary_offsets.push(so),
            Record::DataEnd(_) => self.data_end_at = Some(offset),
            _ => {}
        }
        Ok(())
    }
}

fn scan(buf: &[u8], cut: bool) -> Res<File> {
    let mut f = File::default();
    let mut r = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_emit_chunks(true)
            .with_validate_chunk_crcs(true)
            .with_validate_data_section_crc(true)
            .with_validate_summary_section_crc(true)
            .with_check_finishes_after_end_magic(true)
            .with_skip_end_magic(cut)
            .with_record_length_limit(LIMIT),
    );
    let mut rest = buf;
    let mut next = 8u64;
    let mut summary = false;
    while let Some(ev) = r.next_event() {
        match ev {
            Err(e) => {
                // a file cut short ends inside a record: only that is taken
                if cut && matches!(e, mcap::McapError::UnexpectedEof) {
                    break; // what came before the cut is checked below
                }
                return Err(format!("at offset {next}: {e} ({e:?})"));
            }
            Ok(LinearReadEvent::ReadRequest(need)) => {
                let n = need.min(rest.len());
                r.insert(n).copy_from_slice(&rest[..n]);
                r.notify_read(n);
                rest = &rest[n..];
            }
            Ok(LinearReadEvent::Record { opcode, data }) => {
                let offset = next;
                next += 9 + data.len() as u64;
                let data = data.to_vec();
                f.top_record(opcode, &data, offset, summary)?;
                summary |= opcode == 0x0f;
            }
        }
    }
    Ok(f)
}

fn check_overlap(f: &File) -> Res<()> {
    let mut by_start: Vec<&Chunk> = f.chunks.iter().collect();
    by_start.sort_by_key(|c| c.header.message_start_time);
    let mut end: Option<(u64, u64)> = None;
    for c in by_start {
        if let Some((e, at)) = end {
            if c.header.message_start_time <= e {
                return Err(format!("chunks at offsets {at} and {} overlap in log time \
                                    (a tick's messages in two chunks?)", c.offset));
            }
        }
        if end.map_or(true, |(e, _)| c.header.message_end_time > e) {
            end = Some((c.header.message_end_time, c.offset));
        }
    }
    Ok(())
}

fn check_complete(buf: &[u8], f: &File) -> Res<()> {
    let footer_at = f.footer_at.ok_or("no footer")?;
    let data_end_at = f.data_end_at.ok_or("no data end")?;
    let footer = match mcap::read::footer(buf) {
        Ok(x) => x,
        Err(e) => return Err(format!("footer: {e}")),
    };
    if footer_at as usize + 9 + 20 + 8 != buf.len() {
        return Err(format!("footer at offset {footer_at} is not the last record"));
    }
    let summary_start = data_end_at + 9 + 4;
    if footer.summary_start != 0 && footer.summary_start != summary_start {
        return Err(format!("footer: summary start {}, the summary starts at {summary_start}",
                           footer.summary_start));
    }
    // the summary offsets: each group holds records of its opcode only
    let first_offset = f.top.iter().find(|(_, op)| *op == 0x0e).map(|(at, _)| *at);
    if footer.summary_offset_start != first_offset.unwrap_or(0) {
        return Err(format!("footer: summary offset start {}, the first summary offset is at {:?}",
                           footer.summary_offset_start, first_offset));
    }
    for so in &f.summary_offsets {
        let end = so.group_start + so.group_length;
        let group: Vec<_> = f.top.iter().filter(|(at, _)| *at >= so.group_start && *at < end)
            .collect();
        if so.group_length == 0 {
            continue; // an empty group (the Python writer's): nothing to point at
        }
        if group.is_empty() || group[0].0 != so.group_start
            || group.iter().any(|(_, op)| *op != so.group_opcode)
        {
            return Err(format!("summary offset for opcode {:#04x} at {}: not a group of those",
                               so.group_opcode, so.group_start));
        }
    }
    // the statistics
    let s = f.stats.as_ref().ok_or("no statistics in the summary")?;
    if s.message_count != f.messages || s.channel_message_counts != f.per_channel
        || s.chunk_count as usize != f.chunks.len() || s.channel_count as usize != f.channels.len()
        || s.schema_count as usize != f.schemas
        || (f.messages > 0 && (Some(s.message_start_time) != f.first
                               || Some(s.message_end_time) != f.last))
    {
        return Err(format!("statistics {s:?} disagree with the file: {} messages {:?}, {} \
                            chunks, {} channels, {} schemas, log times {:?}..{:?}", f.messages,
                           f.per_channel, f.chunks.len(), f.channels.len(), f.schemas, f.first,
                           f.last));
    }
    // every chunk has its index, and every message its index entry
    if f.chunk_indexes.len() != f.chunks.len() {
        return Err(format!("{} chunk indexes for {} chunks", f.chunk_indexes.len(),
                           f.chunks.len()));
    }
    for (ci, c) in f.chunk_indexes.iter().zip(&f.chunks) {
        let h = &c.header;
        if ci.chunk_start_offset != c.offset || ci.chunk_length != c.length
            || ci.message_start_time != h.message_start_time
            || ci.message_end_time != h.message_end_time || ci.compression != h.compression
            || ci.compressed_size != h.compressed_size
            || ci.uncompressed_size != h.uncompressed_size
        {
            return Err(format!("chunk index {ci:?} disagrees with the chunk at offset {}",
                               c.offset));
        }
        let mut indexed: Vec<(u64, u16, u64)> = Vec::new();
        for (channel, entries) in f.message_indexes.get(&c.offset).into_iter().flatten() {
            let at = f.top.iter().find(|(at, op)| *op == 0x07
                && ci.message_index_offsets.get(channel) == Some(at));
            if at.is_none() {
                return Err(format!("chunk at offset {}: channel {channel}'s message index is \
                                    not where its chunk index says", c.offset));
            }
            indexed.extend(entries.iter().map(|(t, o)| (*o, *channel, *t)));
        }
        indexed.sort();
        let mut actual = c.messages.clone();
        actual.sort();
        if indexed != actual {
            return Err(format!("chunk at offset {}: its message indexes do not list its \
                                messages", c.offset));
        }
    }
    if mcap::Summary::read(buf).map_err(|e| format!("summary: {e}"))?.is_none() {
        return Err("no summary".into());
    }
    Ok(())
}

fn check(path: &str, cut: bool) -> Res<String> {
    let buf = std::fs::read(path).map_err(|e| format!("cannot read: {e}"))?;
    let f = scan(&buf, cut)?;
    if f.chunks.is_empty() {
        return Err("no complete chunk".into());
    }
    check_overlap(&f)?;
    if !cut {
        check_complete(&buf, &f)?;
    }
    let mut comp: Vec<&str> = f.chunks.iter().map(|c| c.header.compression.as_str()).collect();
    comp.dedup();
    Ok(format!("ok: {} messages in {} chunks (compression {:?}), log times {}..{}",
               f.messages, f.chunks.len(), comp, f.first.unwrap_or(0), f.last.unwrap_or(0)))
}

fn main() -> ExitCode {
    let mut cut = false;
    let mut status = ExitCode::SUCCESS;
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() {
        eprintln!("usage: roz-mcap-strict FILE... [--cut FILE...]");
        return ExitCode::from(2);
    }
    for a in args {
        if a == "--cut" {
            cut = true;
            continue;
        }
        match check(&a, cut) {
            Ok(s) => println!("{a}: {s}"),
            Err(e) => {
                println!("{a}: error: {e}");
                status = ExitCode::FAILURE;
            }
        }
    }
    status
}
