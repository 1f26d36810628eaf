"""The S3 side of ulog-cli/tests/object_store.rs, with clients we did not write:
boto3 puts logs into a bucket of the S3 server the test started, and pyarrow's S3
filesystem reads a dataset `ulog parquet` wrote there.

    s3_check.py upload BUCKET PREFIX [--public] FILE...   # logs into s3://BUCKET/PREFIX/
    s3_check.py put BUCKET KEY TEXT                       # one object
    s3_check.py keys BUCKET PREFIX                        # JSON: the keys below PREFIX
    s3_check.py compare BUCKET PREFIX LOCAL_DATASET       # JSON: the dataset in the
        bucket (read by pyarrow.fs.S3FileSystem) against the local one (pyarrow.parquet)
    s3_check.py consistent BUCKET PREFIX                  # JSON: logs.parquet against
        the topic files (every listed log has its files, every file its log)
    s3_check.py tls-cert DIR                              # DIR/ca.pem, cert.pem, key.pem:
        an authority and the certificate for 127.0.0.1 it signed (`cryptography`)

The endpoint and credentials come from the standard AWS environment, as `ulog`'s.
"""

import json
import os
import sys
from urllib.parse import urlparse

import boto3
import pyarrow.fs
import pyarrow.parquet as pq

TABLES = ["logs", "parameters", "messages", "formats", "analysis", "flights"]


def client():
    return boto3.client("s3", endpoint_url=os.environ["AWS_ENDPOINT_URL"])


def keys(bucket, prefix):
    out = []
    for page in client().get_paginator("list_objects_v2").paginate(Bucket=bucket, Prefix=prefix):
        out.extend(o["Key"] for o in page.get("Contents", []))
    return sorted(out)


def s3fs():
    endpoint = urlparse(os.environ["AWS_ENDPOINT_URL"])
    return pyarrow.fs.S3FileSystem(
        endpoint_override=endpoint.netloc,
        scheme=endpoint.scheme,
        access_key=os.environ["AWS_ACCESS_KEY_ID"],
        secret_key=os.environ["AWS_SECRET_ACCESS_KEY"],
        region=os.environ.get("AWS_DEFAULT_REGION", "us-east-1"),
    )


def rows(table):
    """The rows as dicts, NaN made comparable (NaN != NaN)."""

    def plain(v):
        if isinstance(v, float) and v != v:
            return "NaN"
        if isinstance(v, list):
            return [plain(x) for x in v]
        if isinstance(v, dict):
            return {k: plain(x) for k, x in v.items()}
        return v

    return [plain(r) for r in table.to_pylist()]


def compare(bucket, prefix, local):
    """Each table and topic file of the dataset in the bucket read by pyarrow's S3
    filesystem, against the local dataset's: the same files, the same schemas and
    rows, and the same bytes, but for `logs.parquet`, whose `path` column is a URL
    there and a path here."""
    fs = s3fs()
    remote = f"{bucket}/{prefix}"
    selector = pyarrow.fs.FileSelector(remote, recursive=True)
    remote_files = sorted(
        i.path[len(remote) + 1 :] for i in fs.get_file_info(selector) if i.type == pyarrow.fs.FileType.File
    )
    local_files = sorted(
        os.path.relpath(os.path.join(d, f), local).replace(os.sep, "/")
        for d, _, fs_ in os.walk(local)
        for f in fs_
    )
    differ = []
    for rel in sorted(set(remote_files) & set(local_files)):
        there = pq.read_table(f"{remote}/{rel}", filesystem=fs)
        here = pq.read_table(os.path.join(local, rel))
        if there.schema != here.schema:
            differ.append(f"{rel}: schema")
            continue
        a, b = rows(there), rows(here)
        if rel == "logs.parquet":
            # The path column says where each log was read from.
            a = sorted(({**r, "path": None} for r in a), key=lambda r: r["log_id"])
            b = sorted(({**r, "path": None} for r in b), key=lambda r: r["log_id"])
        if a != b:
            differ.append(f"{rel}: rows")
        elif rel != "logs.parquet":
            with fs.open_input_file(f"{remote}/{rel}") as f:
                if f.read() != open(os.path.join(local, rel), "rb").read():
                    differ.append(f"{rel}: bytes")
    paths = [r["path"] for r in rows(pq.read_table(f"{remote}/logs.parquet", filesystem=fs))]
    return {
        "remote_only": sorted(set(remote_files) - set(local_files)),
        "local_only": sorted(set(local_files) - set(remote_files)),
        "compared": len(set(remote_files) & set(local_files)),
        "differ": differ,
        "paths": paths,
    }


def consistent(bucket, prefix):
    fs = s3fs()
    listed = set()
    try:
        logs = pq.read_table(f"{bucket}/{prefix}/logs.parquet", filesystem=fs)
        listed = set(logs.column("log_id").to_pylist())
        topics = dict(zip(logs.column("log_id").to_pylist(), logs.column("topics").to_pylist()))
    except FileNotFoundError:
        topics = {}
    files = {}
    for key in keys(bucket, prefix + "/"):
        parts = key[len(prefix) + 1 :].split("/")
        # Topic files (`_schemas/` holds the union schemas, not a log's rows).
        if len(parts) == 2 and parts[1].endswith(".parquet") and not parts[0].startswith("_"):
            files.setdefault(parts[1][: -len(".parquet")], []).append(parts[0])
    return {
        "logs": sorted(listed),
        "without_files": sorted(i for i in listed if topics.get(i) and i not in files),
        "files_without_log": sorted(i for i in files if i not in listed),
        "lock": any(k.endswith(".ulog-dataset.lock") for k in keys(bucket, prefix + "/")),
    }


def tls_cert(folder):
    """A certificate authority (ca.pem, which clients are told to trust) and the
    server's certificate for 127.0.0.1 that it signed (cert.pem, key.pem): TLS
    libraries refuse an authority's certificate as a server's."""
    import datetime
    import ipaddress

    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

    now = datetime.datetime.now(datetime.timezone.utc)

    def made(subject, issuer, key, signer, ca):
        builder = (
            x509.CertificateBuilder()
            .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, subject)]))
            .issuer_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, issuer)]))
            .public_key(key.public_key())
            .serial_number(x509.random_serial_number())
            .not_valid_before(now - datetime.timedelta(days=1))
            .not_valid_after(now + datetime.timedelta(days=7))
            .add_extension(x509.BasicConstraints(ca=ca, path_length=None), critical=True)
        )
        if not ca:
            builder = builder.add_extension(
                x509.SubjectAlternativeName([x509.IPAddress(ipaddress.ip_address("127.0.0.1"))]),
                critical=False,
            ).add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH]), critical=False)
        return builder.sign(signer, hashes.SHA256())

    ca_key = ec.generate_private_key(ec.SECP256R1())
    ca = made("ulog test authority", "ulog test authority", ca_key, ca_key, True)
    key = ec.generate_private_key(ec.SECP256R1())
    cert = made("127.0.0.1", "ulog test authority", key, ca_key, False)
    pem = serialization.Encoding.PEM
    with open(os.path.join(folder, "ca.pem"), "wb") as f:
        f.write(ca.public_bytes(pem))
    with open(os.path.join(folder, "cert.pem"), "wb") as f:
        f.write(cert.public_bytes(pem) + ca.public_bytes(pem))
    with open(os.path.join(folder, "key.pem"), "wb") as f:
        f.write(key.private_bytes(pem, serialization.PrivateFormat.PKCS8,
                                  serialization.NoEncryption()))


def main():
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd == "tls-cert":
        tls_cert(args[0])
        return
    if cmd == "upload":
        bucket, prefix, rest = args[0], args[1], args[2:]
        public = "--public" in rest
        c = client()
        try:
            c.create_bucket(Bucket=bucket)
        except c.exceptions.BucketAlreadyOwnedByYou:
            pass
        for f in (r for r in rest if r != "--public"):
            key = f"{prefix}/{os.path.basename(f)}"
            c.upload_file(f, bucket, key)
            if public:
                c.put_object_acl(Bucket=bucket, Key=key, ACL="public-read")
    elif cmd == "put":
        client().put_object(Bucket=args[0], Key=args[1], Body=args[2].encode())
    elif cmd == "keys":
        print(json.dumps(keys(args[0], args[1])))
    elif cmd == "compare":
        print(json.dumps(compare(*args)))
    elif cmd == "consistent":
        print(json.dumps(consistent(*args)))
    else:
        sys.exit(f"unknown command {cmd}")


if __name__ == "__main__":
    main()
