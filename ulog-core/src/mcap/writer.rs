//! The MCAP file itself: the records of the mcap crate, laid out as its `Writer` lays
//! them out for the same calls (uncompressed, the same bytes), but each chunk built
//! whole in memory and compressed on other threads while the pass builds the next.
//!
//! Why not the crate's `Writer`: it feeds each record to the zstd stream in pieces
//! (opcode, length, header, data) on the thread of the pass, and keeps books per
//! message in maps. On a 295 MB log (5.9 M messages, 567 MB of records) that was
//! 2.91 s against 1.12 s for `ulog csv`. Here the pass and CDR take 0.35 s of CPU
//! and zstd 1.0 s, on two threads beside the pass.
//!
//! Compressed chunks: one zstd frame per chunk at the crate's settings (level −1, no
//! content size in the frame), made in one call instead of a stream of small writes.
//! zstd then reads the chunk in place instead of copying it into its window and
//! searching two segments of memory: 8% less CPU on log61 ×90, and a few matches come
//! out otherwise (events ×20: 23,745,538 bytes against 23,745,596). The chunks hold
//! the same records, with the same CRCs, in other compressed bytes.
//!
//! Memory: the open chunk, and at most [`IN_FLIGHT_PER_WORKER`] chunks per worker
//! sealed and not yet written (each with its compressed copy), whatever the size of
//! the log.

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::io::{self, Cursor, Write};
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::thread::JoinHandle;

use ::mcap::records::{
    op, Channel, ChunkHeader, ChunkIndex, DataEnd, MessageHeader, MessageIndexEntry, Metadata,
    MetadataIndex, SchemaHeader, Statistics, SummaryOffset,
};
use ::mcap::{McapError, MAGIC};
use binrw::BinWrite;

/// Chunks sealed and not yet written, per worker: one being compressed, one waiting
/// for it. Fewer stalls the pass while a worker finishes; more only holds memory.
const IN_FLIGHT_PER_WORKER: usize = 2;

/// Compression threads at most. Compression is the larger part of the work (on the
/// 295 MB log: 1.0 s of zstd against 0.35 s for the pass and CDR), so with one worker
/// the pass waits for it; two keep two cores busy, and more cores would need a faster
/// pass to pay off.
const MAX_WORKERS: usize = 2;

/// Appends a record to `out`: its opcode, its length, then the body `body` writes.
fn record(
    out: &mut Vec<u8>,
    opcode: u8,
    body: impl FnOnce(&mut Cursor<&mut Vec<u8>>) -> binrw::BinResult<()>,
) -> Result<(), McapError> {
    out.push(opcode);
    let at = out.len();
    out.extend_from_slice(&[0; 8]);
    let mut cursor = Cursor::new(&mut *out);
    cursor.set_position((at + 8) as u64);
    body(&mut cursor)?;
    let len = (out.len() - at - 8) as u64;
    out[at..at + 8].copy_from_slice(&len.to_le_bytes());
    Ok(())
}

/// A schema record: its header, then its data with a 32-bit length.
fn schema_record(out: &mut Vec<u8>, header: &SchemaHeader, data: &[u8]) -> Result<(), McapError> {
    record(out, op::SCHEMA, |c| {
        header.write_le(c)?;
        (data.len() as u32).write_le(c)?;
        c.write_all(data)?;
        Ok(())
    })
}

/// A chunk handed to the worker: its records, and a spare buffer for the compressed
/// bytes.
struct Job {
    records: Vec<u8>,
    spare: Vec<u8>,
}

/// A chunk back from the worker.
struct Done {
    records: Vec<u8>,
    /// The compressed records (empty without compression).
    compressed: io::Result<Vec<u8>>,
    /// CRC-32 of the records.
    crc: u32,
}

/// What a sealed chunk's record and index need besides its bytes.
struct Sealed {
    bounds: (u64, u64),
    /// Each channel's messages in the chunk, by channel id.
    indexes: Vec<Vec<MessageIndexEntry>>,
}

/// The worker: CRC and compression of each chunk, in the order given.
fn compress(jobs: Receiver<Job>, done: mpsc::Sender<Done>, level: Option<i32>) {
    let mut encoder = None;
    for Job { records, spare } in jobs {
        let crc = crc32fast::hash(&records);
        let compressed = match level {
            Some(level) => zstd_chunk(&mut encoder, level, &records, spare),
            None => Ok(spare),
        };
        if done
            .send(Done {
                records,
                compressed,
                crc,
            })
            .is_err()
        {
            return;
        }
    }
}

/// A chunk's records as one zstd frame at `level`, without the content size (as the
/// crate's stream writes its frames); the context kept from chunk to chunk.
fn zstd_chunk(
    encoder: &mut Option<zstd::zstd_safe::CCtx<'static>>,
    level: i32,
    records: &[u8],
    mut out: Vec<u8>,
) -> io::Result<Vec<u8>> {
    use zstd::zstd_safe::{CCtx, CParameter};
    let zerr = |code| io::Error::other(zstd::zstd_safe::get_error_name(code));
    let cctx = match encoder {
        Some(c) => c,
        None => {
            let mut c = CCtx::create();
            c.set_parameter(CParameter::CompressionLevel(level))
                .map_err(zerr)?;
            c.set_parameter(CParameter::ContentSizeFlag(false))
                .map_err(zerr)?;
            encoder.insert(c)
        }
    };
    out.clear();
    out.reserve(zstd::zstd_safe::compress_bound(records.len()));
    cctx.compress2(&mut out, records).map_err(zerr)?;
    Ok(out)
}

/// Writes an MCAP file to `W`, as the crate's `Writer` with chunks, message indexes,
/// statistics, summary offsets and every CRC would.
pub(super) struct McapWriter<W: Write> {
    out: W,
    /// Bytes written to `out`.
    pos: u64,
    /// CRC of the data section so far.
    crc: crc32fast::Hasher,
    chunk_bytes: u64,
    /// The chunks' compression as the chunk records name it.
    compression: &'static str,
    /// The open chunk's records (none open while empty).
    chunk: Vec<u8>,
    /// The open chunk's earliest and latest message times.
    bounds: Option<(u64, u64)>,
    /// The open chunk's messages by channel id.
    indexes: Vec<Vec<MessageIndexEntry>>,
    /// Chunks sealed, in order, not yet written.
    pending: VecDeque<Sealed>,
    /// Chunks sealed so far: chunk `n` goes to worker `n % workers.len()`, and comes
    /// back from it in order.
    sealed: usize,
    /// Buffers back from written chunks, for the next ones.
    spare_records: Vec<Vec<u8>>,
    spare_compressed: Vec<Vec<u8>>,
    spare_indexes: Vec<Vec<Vec<MessageIndexEntry>>>,
    workers: Vec<Worker>,
    /// Schemas by content, to give the same content the same id as the crate does.
    schema_ids: HashMap<(String, String, Vec<u8>), u16>,
    schemas: Vec<(SchemaHeader, Vec<u8>)>,
    channel_ids: HashMap<(String, u16, String, BTreeMap<String, String>), u16>,
    channels: Vec<Channel>,
    /// Messages by channel id.
    counts: Vec<u64>,
    message_bounds: Option<(u64, u64)>,
    chunk_indexes: Vec<ChunkIndex>,
    metadata_indexes: Vec<MetadataIndex>,
    /// Records written outside chunks, built here first.
    scratch: Vec<u8>,
}

impl<W: Write> McapWriter<W> {
    /// Starts the file: magic and header. `zstd_level`: chunks compressed with zstd
    /// at that level, else stored as they are.
    pub(super) fn create(
        out: W,
        profile: &str,
        library: &str,
        chunk_bytes: u64,
        zstd_level: Option<i32>,
    ) -> Result<Self, McapError> {
        let n = std::thread::available_parallelism().map_or(1, |n| n.get().min(MAX_WORKERS));
        let workers = (0..n)
            .map(|_| Worker::start(zstd_level))
            .collect::<io::Result<Vec<_>>>()?;
        let mut w = McapWriter {
            out,
            pos: 0,
            crc: crc32fast::Hasher::new(),
            chunk_bytes,
            compression: if zstd_level.is_some() { "zstd" } else { "" },
            chunk: Vec::new(),
            bounds: None,
            indexes: Vec::new(),
            pending: VecDeque::new(),
            sealed: 0,
            spare_records: Vec::new(),
            spare_compressed: Vec::new(),
            spare_indexes: Vec::new(),
            workers,
            schema_ids: HashMap::new(),
            schemas: Vec::new(),
            channel_ids: HashMap::new(),
            channels: Vec::new(),
            counts: Vec::new(),
            message_bounds: None,
            chunk_indexes: Vec::new(),
            metadata_indexes: Vec::new(),
            scratch: Vec::new(),
        };
        let mut head = MAGIC.to_vec();
        let header = ::mcap::records::Header {
            profile: profile.to_owned(),
            library: library.to_owned(),
        };
        record(&mut head, op::HEADER, |c| header.write_le(c))?;
        w.put(&head)?;
        Ok(w)
    }

    /// Writes bytes of the data section.
    fn put(&mut self, bytes: &[u8]) -> Result<(), McapError> {
        self.out.write_all(bytes)?;
        self.crc.update(bytes);
        self.pos += bytes.len() as u64;
        Ok(())
    }

    /// The id of a schema of this content, added (in the open chunk) if new.
    pub(super) fn add_schema(
        &mut self,
        name: &str,
        encoding: &str,
        data: &[u8],
    ) -> Result<u16, McapError> {
        let key = (name.to_owned(), encoding.to_owned(), data.to_vec());
        if let Some(&id) = self.schema_ids.get(&key) {
            return Ok(id);
        }
        let id = u16::try_from(self.schemas.len() + 1).map_err(|_| McapError::TooManySchemas)?;
        let header = SchemaHeader {
            id,
            name: name.to_owned(),
            encoding: encoding.to_owned(),
        };
        schema_record(&mut self.chunk, &header, data)?;
        self.schemas.push((header, key.2.clone()));
        self.schema_ids.insert(key, id);
        Ok(id)
    }

    /// The id of a channel of this content, added (in the open chunk) if new.
    pub(super) fn add_channel(
        &mut self,
        schema_id: u16,
        topic: &str,
        message_encoding: &str,
        metadata: &BTreeMap<String, String>,
    ) -> Result<u16, McapError> {
        let key = (
            topic.to_owned(),
            schema_id,
            message_encoding.to_owned(),
            metadata.clone(),
        );
        if let Some(&id) = self.channel_ids.get(&key) {
            return Ok(id);
        }
        if schema_id != 0 && usize::from(schema_id) > self.schemas.len() {
            return Err(McapError::UnknownSchema(topic.to_owned(), schema_id));
        }
        let id = u16::try_from(self.channels.len() + 1).map_err(|_| McapError::TooManyChannels)?;
        let channel = Channel {
            id,
            schema_id,
            topic: key.0.clone(),
            message_encoding: key.2.clone(),
            metadata: key.3.clone(),
        };
        record(&mut self.chunk, op::CHANNEL, |c| channel.write_le(c))?;
        self.channels.push(channel);
        self.channel_ids.insert(key, id);
        self.counts.push(0);
        Ok(id)
    }

    /// Writes a message to a channel added before.
    pub(super) fn write_to_known_channel(
        &mut self,
        header: &MessageHeader,
        data: &[u8],
    ) -> Result<(), McapError> {
        self.write_with(header, |chunk| {
            chunk.extend_from_slice(data);
            true
        })
        .map(|_| ())
    }

    /// Writes a message to a channel added before, its data appended to the chunk
    /// by `encode` (CDR straight into the chunk saves copying each message once, 2%
    /// of the time on a 300 MB log); `false` from it: no message, and `Ok(false)`.
    pub(super) fn write_with(
        &mut self,
        header: &MessageHeader,
        encode: impl FnOnce(&mut Vec<u8>) -> bool,
    ) -> Result<bool, McapError> {
        let id = usize::from(header.channel_id);
        if id == 0 || id > self.channels.len() {
            return Err(McapError::UnknownChannel(
                header.sequence,
                header.channel_id,
            ));
        }
        // Opcode, length and the 22-byte header, the length filled in after.
        let start = self.chunk.len();
        let mut head = [0u8; 31];
        head[0] = op::MESSAGE;
        head[9..11].copy_from_slice(&header.channel_id.to_le_bytes());
        head[11..15].copy_from_slice(&header.sequence.to_le_bytes());
        head[15..23].copy_from_slice(&header.log_time.to_le_bytes());
        head[23..31].copy_from_slice(&header.publish_time.to_le_bytes());
        self.chunk.extend_from_slice(&head);
        if !encode(&mut self.chunk) {
            self.chunk.truncate(start);
            return Ok(false);
        }
        let len = (self.chunk.len() - start - 9) as u64;
        self.chunk[start + 1..start + 9].copy_from_slice(&len.to_le_bytes());
        let t = header.log_time;
        self.message_bounds = Some(
            self.message_bounds
                .map_or((t, t), |(a, b)| (a.min(t), b.max(t))),
        );
        self.counts[id - 1] += 1;
        // As the crate's writer: a chunk past its size is sealed before the next
        // message, not after the message that passes it.
        let start = match start as u64 > self.chunk_bytes {
            true => {
                self.seal_at(start)?;
                0
            }
            false => start,
        };
        self.bounds = Some(self.bounds.map_or((t, t), |(a, b)| (a.min(t), b.max(t))));
        if self.indexes.len() <= id {
            self.indexes.resize_with(id + 1, Vec::new);
        }
        self.indexes[id].push(MessageIndexEntry {
            log_time: t,
            offset: start as u64,
        });
        Ok(true)
    }

    /// Hands the open chunk, if any, to the worker, and writes the chunks it has
    /// finished.
    fn seal(&mut self) -> Result<(), McapError> {
        self.seal_at(self.chunk.len())
    }

    /// Seals the open chunk's first `end` bytes; the rest (one message record) opens
    /// the next chunk.
    fn seal_at(&mut self, end: usize) -> Result<(), McapError> {
        if end == 0 {
            return Ok(());
        }
        let mut fresh = self.spare_records.pop().unwrap_or_else(|| {
            // Room for a chunk and its last record, but not more than 64 MiB ahead:
            // a chunk size may be huge ("never split").
            let room = usize::try_from(self.chunk_bytes).unwrap_or(usize::MAX);
            Vec::with_capacity(room.min(64 << 20).saturating_add(64 * 1024))
        });
        fresh.extend_from_slice(&self.chunk[end..]);
        self.chunk.truncate(end);
        let records = std::mem::replace(&mut self.chunk, fresh);
        self.pending.push_back(Sealed {
            bounds: self.bounds.take().unwrap_or((0, 0)),
            indexes: std::mem::replace(
                &mut self.indexes,
                self.spare_indexes.pop().unwrap_or_default(),
            ),
        });
        let job = Job {
            records,
            spare: self.spare_compressed.pop().unwrap_or_default(),
        };
        let n = self.workers.len();
        self.workers[self.sealed % n].send(job)?;
        self.sealed += 1;
        while self.pending.len() > IN_FLIGHT_PER_WORKER * n {
            self.write_oldest(true)?;
        }
        while self.write_oldest(false)? {}
        Ok(())
    }

    /// Seals the open chunk and writes every chunk sealed.
    fn drain(&mut self) -> Result<(), McapError> {
        self.seal()?;
        while self.write_oldest(true)? {}
        Ok(())
    }

    /// Writes the oldest sealed chunk if its worker has it done (or, with `wait`, when
    /// it has); whether one was written.
    fn write_oldest(&mut self, wait: bool) -> Result<bool, McapError> {
        if self.pending.is_empty() {
            return Ok(false);
        }
        let oldest = self.sealed - self.pending.len();
        let worker = &self.workers[oldest % self.workers.len()];
        let done = match wait {
            true => worker.done.recv().map_err(|_| worker_gone())?,
            false => match worker.done.try_recv() {
                Ok(done) => done,
                Err(mpsc::TryRecvError::Empty) => return Ok(false),
                Err(mpsc::TryRecvError::Disconnected) => return Err(worker_gone()),
            },
        };
        self.write_chunk(done)?;
        Ok(true)
    }

    /// Writes the oldest sealed chunk, back from the worker: the chunk record, then
    /// one message index per channel in it.
    fn write_chunk(&mut self, done: Done) -> Result<(), McapError> {
        let mut sealed = self.pending.pop_front().ok_or_else(worker_gone)?;
        let Done {
            mut records,
            compressed,
            crc,
        } = done;
        let compressed = compressed?;
        let stored: &[u8] = match self.compression {
            "" => &records,
            _ => &compressed,
        };
        let start = self.pos;
        let header = ChunkHeader {
            message_start_time: sealed.bounds.0,
            message_end_time: sealed.bounds.1,
            uncompressed_size: records.len() as u64,
            uncompressed_crc: crc,
            compression: self.compression.to_owned(),
            compressed_size: stored.len() as u64,
        };
        let mut head = std::mem::take(&mut self.scratch);
        head.clear();
        record(&mut head, op::CHUNK, |c| header.write_le(c))?;
        let len = (head.len() - 9 + stored.len()) as u64;
        head[1..9].copy_from_slice(&len.to_le_bytes());
        self.put(&head)?;
        self.put(stored)?;
        let data_end = self.pos;
        let mut message_index_offsets = BTreeMap::new();
        for (id, entries) in sealed.indexes.iter_mut().enumerate() {
            if entries.is_empty() {
                continue;
            }
            message_index_offsets.insert(id as u16, self.pos);
            // A MessageIndex record, laid out by hand: the crate's encoding writes
            // each 16-byte entry field by field, 1.6% of the time on a 300 MB log.
            let bytes = 16 * entries.len();
            head.clear();
            head.push(op::MESSAGE_INDEX);
            head.extend_from_slice(&(2 + 4 + bytes as u64).to_le_bytes());
            head.extend_from_slice(&(id as u16).to_le_bytes());
            head.extend_from_slice(&(bytes as u32).to_le_bytes());
            for e in entries.drain(..) {
                head.extend_from_slice(&e.log_time.to_le_bytes());
                head.extend_from_slice(&e.offset.to_le_bytes());
            }
            self.put(&head)?;
        }
        self.scratch = head;
        self.spare_indexes.push(sealed.indexes);
        self.chunk_indexes.push(ChunkIndex {
            message_start_time: header.message_start_time,
            message_end_time: header.message_end_time,
            chunk_start_offset: start,
            chunk_length: data_end - start,
            message_index_offsets,
            message_index_length: self.pos - data_end,
            compression: header.compression,
            compressed_size: header.compressed_size,
            uncompressed_size: header.uncompressed_size,
        });
        records.clear();
        self.spare_records.push(records);
        self.spare_compressed.push(compressed);
        Ok(())
    }

    /// Writes a metadata record, after the chunks so far.
    pub(super) fn write_metadata(&mut self, metadata: &Metadata) -> Result<(), McapError> {
        self.drain()?;
        let mut bytes = std::mem::take(&mut self.scratch);
        bytes.clear();
        record(&mut bytes, op::METADATA, |c| metadata.write_le(c))?;
        self.metadata_indexes.push(MetadataIndex {
            offset: self.pos,
            length: bytes.len() as u64,
            name: metadata.name.clone(),
        });
        self.put(&bytes)?;
        self.scratch = bytes;
        Ok(())
    }

    /// Writes the last chunk, the end of the data section, the summary (schemas,
    /// channels, statistics, chunk and metadata indexes, the offsets of each group)
    /// and the footer, and flushes.
    pub(super) fn finish(&mut self) -> Result<(), McapError> {
        self.drain()?;
        self.stop_workers()?;
        let mut end = Vec::new();
        let data_section_crc = self.crc.clone().finalize();
        record(&mut end, op::DATA_END, |c| {
            DataEnd { data_section_crc }.write_le(c)
        })?;
        let summary_start = self.pos + end.len() as u64;
        let mut s = Vec::new();
        let mut offsets = Vec::new();
        let mut group = |s: &mut Vec<u8>, opcode: u8, from: usize| {
            offsets.push(SummaryOffset {
                group_opcode: opcode,
                group_start: summary_start + from as u64,
                group_length: (s.len() - from) as u64,
            })
        };
        if !self.schemas.is_empty() {
            let from = s.len();
            for (header, data) in &self.schemas {
                schema_record(&mut s, header, data)?;
            }
            group(&mut s, op::SCHEMA, from);
        }
        if !self.channels.is_empty() {
            let from = s.len();
            for channel in &self.channels {
                record(&mut s, op::CHANNEL, |c| channel.write_le(c))?;
            }
            group(&mut s, op::CHANNEL, from);
        }
        let (message_start_time, message_end_time) = self.message_bounds.unwrap_or((0, 0));
        let statistics = Statistics {
            message_count: self.counts.iter().sum(),
            schema_count: self.schemas.len() as u16,
            channel_count: self.channels.len() as u32,
            attachment_count: 0,
            metadata_count: self.metadata_indexes.len() as u32,
            chunk_count: self.chunk_indexes.len() as u32,
            message_start_time,
            message_end_time,
            channel_message_counts: self
                .counts
                .iter()
                .enumerate()
                .filter(|(_, &n)| n > 0)
                .map(|(i, &n)| (i as u16 + 1, n))
                .collect(),
        };
        let from = s.len();
        record(&mut s, op::STATISTICS, |c| statistics.write_le(c))?;
        group(&mut s, op::STATISTICS, from);
        if !self.chunk_indexes.is_empty() {
            let from = s.len();
            for index in &self.chunk_indexes {
                record(&mut s, op::CHUNK_INDEX, |c| index.write_le(c))?;
            }
            group(&mut s, op::CHUNK_INDEX, from);
        }
        if !self.metadata_indexes.is_empty() {
            let from = s.len();
            for index in &self.metadata_indexes {
                record(&mut s, op::METADATA_INDEX, |c| index.write_le(c))?;
            }
            group(&mut s, op::METADATA_INDEX, from);
        }
        let summary_offset_start = summary_start + s.len() as u64;
        for offset in offsets {
            record(&mut s, op::SUMMARY_OFFSET, |c| offset.write_le(c))?;
        }
        // The footer's CRC covers the summary and the footer up to the CRC itself.
        s.push(op::FOOTER);
        s.extend_from_slice(&20u64.to_le_bytes());
        s.extend_from_slice(&summary_start.to_le_bytes());
        s.extend_from_slice(&summary_offset_start.to_le_bytes());
        let summary_crc = crc32fast::hash(&s);
        s.extend_from_slice(&summary_crc.to_le_bytes());
        s.extend_from_slice(MAGIC);
        self.out.write_all(&end)?;
        self.out.write_all(&s)?;
        self.out.flush()?;
        Ok(())
    }

    /// Ends the workers and waits for them.
    fn stop_workers(&mut self) -> Result<(), McapError> {
        let mut result = Ok(());
        for w in &mut self.workers {
            w.jobs = None;
            if let Some(Err(_)) = w.thread.take().map(JoinHandle::join) {
                result = Err(worker_gone());
            }
        }
        result
    }
}

impl<W: Write> Drop for McapWriter<W> {
    fn drop(&mut self) {
        let _ = self.stop_workers();
    }
}

/// A compression thread, with its queue each way.
struct Worker {
    /// Closed (`None`) to end it.
    jobs: Option<SyncSender<Job>>,
    done: Receiver<Done>,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    fn start(zstd_level: Option<i32>) -> io::Result<Worker> {
        let (jobs, job_rx) = mpsc::sync_channel(1);
        let (done_tx, done) = mpsc::channel();
        let thread = std::thread::Builder::new()
            .name("mcap-chunks".into())
            .spawn(move || compress(job_rx, done_tx, zstd_level))?;
        Ok(Worker {
            jobs: Some(jobs),
            done,
            thread: Some(thread),
        })
    }

    fn send(&self, job: Job) -> Result<(), McapError> {
        let jobs = self.jobs.as_ref().ok_or_else(worker_gone)?;
        jobs.send(job).map_err(|_| worker_gone())
    }
}

/// The worker stopped before its work was done (it panicked).
fn worker_gone() -> McapError {
    McapError::Io(io::Error::other("the chunk compression thread stopped"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use ::mcap::{Compression, WriteOptions};

    /// What the pass calls, on either writer.
    trait Calls {
        fn schema(&mut self, name: &str, data: &[u8]) -> u16;
        fn channel(&mut self, schema: u16, topic: &str, meta: &BTreeMap<String, String>) -> u16;
        fn message(&mut self, header: &MessageHeader, data: &[u8]);
        fn metadata(&mut self, metadata: &Metadata);
    }

    impl<W: Write> Calls for McapWriter<W> {
        fn schema(&mut self, name: &str, data: &[u8]) -> u16 {
            self.add_schema(name, "ros2msg", data).unwrap()
        }
        fn channel(&mut self, schema: u16, topic: &str, meta: &BTreeMap<String, String>) -> u16 {
            self.add_channel(schema, topic, "cdr", meta).unwrap()
        }
        fn message(&mut self, header: &MessageHeader, data: &[u8]) {
            self.write_to_known_channel(header, data).unwrap()
        }
        fn metadata(&mut self, metadata: &Metadata) {
            self.write_metadata(metadata).unwrap()
        }
    }

    impl<W: Write + std::io::Seek> Calls for ::mcap::Writer<W> {
        fn schema(&mut self, name: &str, data: &[u8]) -> u16 {
            self.add_schema(name, "ros2msg", data).unwrap()
        }
        fn channel(&mut self, schema: u16, topic: &str, meta: &BTreeMap<String, String>) -> u16 {
            self.add_channel(schema, topic, "cdr", meta).unwrap()
        }
        fn message(&mut self, header: &MessageHeader, data: &[u8]) {
            self.write_to_known_channel(header, data).unwrap()
        }
        fn metadata(&mut self, metadata: &Metadata) {
            self.write_metadata(metadata).unwrap()
        }
    }

    /// The same calls on this writer and on the crate's: schemas (one twice),
    /// channels, messages over many small chunks, a channel added after a chunk,
    /// metadata between chunks.
    fn calls(w: &mut impl Calls) {
        let meta = BTreeMap::from([("ulog.topic".to_owned(), "a".to_owned())]);
        let s1 = w.schema("px4_msgs/msg/A", b"uint64 timestamp\n");
        let a = w.channel(s1, "/fmu/out/a", &meta);
        assert_eq!(w.schema("px4_msgs/msg/A", b"uint64 timestamp\n"), s1);
        let b = w.channel(s1, "/fmu/out/a_1", &BTreeMap::new());
        for i in 0..500u64 {
            let channel_id = if i % 3 == 0 { b } else { a };
            let data: Vec<u8> = (0..(i % 50) as u8).collect();
            // Times out of order now and then, as a log's topics are.
            let t = 1_000 + i * 10 - (i % 7) * 15;
            let header = MessageHeader {
                channel_id,
                sequence: i as u32,
                log_time: t,
                publish_time: t,
            };
            w.message(&header, &data);
            if i == 200 {
                let s2 = w.schema("rcl_interfaces/msg/Log", b"uint8 level\n");
                w.channel(s2, "/rosout", &BTreeMap::new());
                w.metadata(&Metadata {
                    name: "ulog_info".into(),
                    metadata: BTreeMap::from([("sys_name".into(), "PX4".into())]),
                });
            }
        }
        w.metadata(&Metadata {
            name: "ulog_file".into(),
            metadata: BTreeMap::new(),
        });
    }

    fn ours(zstd: Option<i32>) -> Vec<u8> {
        let mut out = Vec::new();
        let mut w = McapWriter::create(&mut out, "ros2", "test", 700, zstd).unwrap();
        calls(&mut w);
        w.finish().unwrap();
        drop(w);
        out
    }

    fn crates(zstd: bool) -> Vec<u8> {
        let mut out = std::io::Cursor::new(Vec::new());
        let mut w = WriteOptions::new()
            .profile("ros2")
            .library("test")
            .compression(zstd.then_some(Compression::Zstd))
            .chunk_size(Some(700))
            .compression_level(1)
            .compression_threads(0)
            .create(&mut out)
            .unwrap();
        calls(&mut w);
        w.finish().unwrap();
        drop(w);
        out.into_inner()
    }

    #[test]
    fn uncompressed_files_are_the_crates_bytes() {
        assert_eq!(ours(None), crates(false));
    }

    /// zstd in one call per chunk compresses the same records to other bytes than
    /// the crate's stream of small writes: every record read back is the same.
    #[test]
    fn compressed_files_read_back_as_the_crates() {
        let (a, b) = (ours(Some(1)), crates(true));
        let records = |bytes: &[u8]| -> Vec<String> {
            ::mcap::read::LinearReader::new(bytes)
                .unwrap()
                .map(|r| r.unwrap())
                .flat_map(|r| match r {
                    ::mcap::records::Record::Chunk { header, data } => {
                        let mut records = vec![format!(
                            "chunk {} {} {} {}",
                            header.message_start_time,
                            header.message_end_time,
                            header.uncompressed_size,
                            header.uncompressed_crc
                        )];
                        let raw = zstd::decode_all(&data[..]).unwrap();
                        assert_eq!(raw.len() as u64, header.uncompressed_size);
                        assert_eq!(crc32fast::hash(&raw), header.uncompressed_crc);
                        records.push(format!("{raw:?}"));
                        records
                    }
                    // Offsets and sizes after the first chunk differ with its size.
                    ::mcap::records::Record::ChunkIndex(_)
                    | ::mcap::records::Record::MetadataIndex(_)
                    | ::mcap::records::Record::SummaryOffset(_)
                    | ::mcap::records::Record::DataEnd(_)
                    | ::mcap::records::Record::Footer(_) => Vec::new(),
                    other => vec![format!("{other:?}")],
                })
                .collect()
        };
        let (ra, rb) = (records(&a), records(&b));
        assert!(ra.len() > 20, "{} records", ra.len());
        assert_eq!(ra, rb);
        let messages = |bytes: &[u8]| -> Vec<(u16, u32, u64, Vec<u8>)> {
            ::mcap::MessageStream::new(bytes)
                .unwrap()
                .map(|m| {
                    let m = m.unwrap();
                    (m.channel.id, m.sequence, m.log_time, m.data.into_owned())
                })
                .collect()
        };
        assert_eq!(messages(&a).len(), 500);
        assert_eq!(messages(&a), messages(&b));
    }
}
